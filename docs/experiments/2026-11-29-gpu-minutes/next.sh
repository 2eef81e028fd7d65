#!/usr/bin/env bash
# NEXT.md's device call, from the repository root on the lent GPU, with runs/gpu-minutes/r and .whl/ carried:
#   COMMIT=<rev> bash docs/experiments/2026-11-29-gpu-minutes/next.sh
# LIMIT_S: seconds the whole call may take (default 570, for timeout_s=600); BENCH=0 leaves the benchmark out (a
# second call in one loan). TINY=1: CPU sizes and seconds of training (the check before a loan). Output in $OUT.
set -uo pipefail
start=$(date +%s)
limit=${LIMIT_S:-570}
if [ "${TINY:-0}" = 1 ]; then
  kinetix=${KINETIX:-.venv/bin/kinetix}
else
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl \
    || exit 1
  export PYTHONPATH=/tmp/site:$PWD/src
  mkdir -p /tmp/bin
  printf '#!/bin/sh\nexec python3 -c "import sys; from kinetix_cli.cli.app import main; sys.argv[0] = \\"kinetix\\"; main()" "$@"\n' >/tmp/bin/kinetix
  chmod +x /tmp/bin/kinetix
  kinetix=/tmp/bin/kinetix
fi
export PYTHONUNBUFFERED=1
[ -f runs/gpu-minutes/r/config.yaml ] || { echo "runs/gpu-minutes/r: not carried" >&2; exit 2; }
{ date; nvidia-smi -L; nvidia-smi --query-gpu=driver_version --format=csv,noheader
  python3 -c "import sys, jax, flax, optax; print(sys.version.split()[0], 'jax', jax.__version__, 'flax', flax.__version__, 'optax', optax.__version__)"
  echo "${COMMIT:-unknown}"; } >"$OUT/versions.txt" 2>&1

if [ "${BENCH:-1}" = 1 ]; then
  SFL_SECONDS=0 TINY=${TINY:-0} KINETIX=$kinetix PYTHON=${PYTHON:-python3} benchmarks/gpu.sh /tmp/g 2>&1 \
    | tee "$OUT/gpu.log"
  cp /tmp/g/engine-m.json /tmp/g/train-m.json /tmp/g/train-m-paper.json "$OUT/" 2>/dev/null
  echo "benchmark seconds: $(($(date +%s) - start))" | tee -a "$OUT/gpu.log"
fi

rm -rf /tmp/r && cp -r runs/gpu-minutes/r /tmp/r
before=$(sed -n 's/^  minutes: //p' /tmp/r/config.yaml)
minutes=$(python3 -c "print(round($before + max(0.1, ($limit - ($(date +%s) - $start) - 60) / 60), 2))")
echo "training from $before to $minutes minutes" | tee -a "$OUT/gpu.log"
"$kinetix" pretrain --config /tmp/r/config.yaml --run-dir /tmp/r --resume --set run.minutes="$minutes" 2>&1 \
  | tail -20 | tee "$OUT/train.log"
tar -czf "$OUT/run.tar.gz" -C /tmp r
echo "call seconds: $(($(date +%s) - start))" | tee -a "$OUT/gpu.log"
ls -la "$OUT"
