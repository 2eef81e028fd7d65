#!/usr/bin/env bash
# benchmarks/gpu.sh on the lent GPU: the machine's own jax/flax/optax, Jax2D carried as a wheel, kinetix from src/
set -uo pipefail
start=$(date +%s)
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 1
export PYTHONPATH=/tmp/site:$PWD/src PYTHONUNBUFFERED=1
mkdir -p /tmp/bin
printf '#!/bin/sh\nexec python3 -c "import sys; from kinetix_cli.cli.app import main; sys.argv[0] = \\"kinetix\\"; main()" "$@"\n' >/tmp/bin/kinetix
chmod +x /tmp/bin/kinetix
{ date; nvidia-smi -L; nvidia-smi --query-gpu=driver_version --format=csv,noheader
  python3 -c "import sys, jax, flax, optax; print(sys.version.split()[0], 'jax', jax.__version__, 'flax', flax.__version__, 'optax', optax.__version__)"
  echo "$COMMIT"; } >"$OUT/versions.txt" 2>&1
KINETIX=/tmp/bin/kinetix PYTHON=python3 benchmarks/gpu.sh /tmp/g 2>&1 | tee "$OUT/gpu.log"
echo "script seconds: $(($(date +%s) - start))" | tee -a "$OUT/gpu.log"
cp /tmp/g/engine-m.json /tmp/g/train-m.json "$OUT/" 2>/dev/null
cp /tmp/g/sfl/eval.json "$OUT/sfl-eval.json" 2>/dev/null
cp /tmp/g/sfl/metrics.jsonl "$OUT/sfl-metrics.jsonl" 2>/dev/null
cp /tmp/g/sfl/wall_seconds "$OUT/sfl-wall_seconds" 2>/dev/null
tar -czf "$OUT/sfl-run.tar.gz" -C /tmp/g sfl 2>/dev/null
ls -la "$OUT"
