#!/usr/bin/env bash
# PLAN.md's device call, from the repository root on the lent GPU (its own jax/flax/optax; Jax2D as a wheel in .whl/):
#   MIRROR=0|1 COMMIT=<rev> bash docs/experiments/2026-11-29-gpu-minutes/run.sh
# LIMIT_S: seconds the whole call may take (default 570, for timeout_s=600). Everything lands in $OUT.
set -uo pipefail
start=$(date +%s)
limit=${LIMIT_S:-570}
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 1
export PYTHONPATH=/tmp/site:$PWD/src PYTHONUNBUFFERED=1
mkdir -p /tmp/bin
printf '#!/bin/sh\nexec python3 -c "import sys; from kinetix_cli.cli.app import main; sys.argv[0] = \\"kinetix\\"; main()" "$@"\n' >/tmp/bin/kinetix
chmod +x /tmp/bin/kinetix
{ date; nvidia-smi -L; nvidia-smi --query-gpu=driver_version --format=csv,noheader
  python3 -c "import sys, jax, flax, optax; print(sys.version.split()[0], 'jax', jax.__version__, 'flax', flax.__version__, 'optax', optax.__version__)"
  echo "${COMMIT:-unknown}"; } >"$OUT/versions.txt" 2>&1

SFL_SECONDS=0 KINETIX=/tmp/bin/kinetix PYTHON=python3 benchmarks/gpu.sh /tmp/g 2>&1 | tee "$OUT/gpu.log"
cp /tmp/g/engine-m.json /tmp/g/train-m.json /tmp/g/train-m-paper.json "$OUT/" 2>/dev/null
echo "benchmark seconds: $(($(date +%s) - start))" | tee -a "$OUT/gpu.log"

mirror=()
[ "${MIRROR:-0}" = 1 ] && mirror=(--set model.mirror=geometric)
minutes=$(python3 -c "print(round(max(1.0, ($limit - ($(date +%s) - $start) - 60) / 60), 2))")
echo "training for $minutes minutes" | tee -a "$OUT/gpu.log"
/tmp/bin/kinetix pretrain --config experiments/general.yaml --run-dir /tmp/r --set run.seed=0 \
  --set ppo.num_envs=4096 --set curriculum.refresh_every=4 "${mirror[@]}" --set run.minutes="$minutes" \
  --set ppo.total_timesteps=100_000_000_000 --set run.eval_every=0 2>&1 | tail -20 | tee "$OUT/train.log"
tar -czf "$OUT/run.tar.gz" -C /tmp r
echo "call seconds: $(($(date +%s) - start))" | tee -a "$OUT/gpu.log"
ls -la "$OUT"
