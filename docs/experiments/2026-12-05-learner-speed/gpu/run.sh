#!/usr/bin/env bash
# Issue 70's GPU part, one device call (timeout_s=600; about 6 minutes), from the repository root on the lent GPU
# with Jax2D's wheel carried in .whl/ (as ../../2026-11-29-gpu-minutes/PLAN.md), before NEXT.md's call there:
#   bash docs/experiments/2026-12-05-learner-speed/gpu/run.sh
# 1. `kinetix bench train --breakdown` at the paper's sizes: the transformer at 32,768 envs (size m, the reference's
#    64 steps x 8 epochs x 32 minibatches), and rel-mlp 64 at 4,096 envs (size s, the general recipe's update).
# 2. The general recipe at 4,096 envs (curriculum.refresh_every=4, as NEXT.md's run) for 24 updates, twice in new
#    processes on one compile cache: the first compiles and writes it, the second reads it. Each run's wall time,
#    first update and SFL's share of the run (summary.py).
# TINY=1: CPU sizes, seconds (the check here before a loan; KINETIX=.venv/bin/kinetix). Output in $OUT: 8 files.
set -uo pipefail
here=$(dirname "$0")
out=${OUT:?OUT: the folder that comes back}
if [ "${TINY:-0}" = 1 ]; then
  kinetix=${KINETIX:-.venv/bin/kinetix} python=${PYTHON:-.venv/bin/python}
  common=(--steps 8 --epochs 1 --minibatches 2 --width 16 --layers 1 --min-time 0.1)
  transformer=(--size s --envs 16 "${common[@]}") rel=(--size s --envs 16 "${common[@]}")
  sfl=(--set ppo.num_envs=16 --set ppo.num_steps=8 --set ppo.num_minibatches=2 --set model.width=16
    --set curriculum.score_levels=8 --set curriculum.score_batch=8 --set curriculum.score_steps=8
    --set curriculum.buffer_size=4 --set ppo.total_timesteps=768)
else
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl \
    || exit 1
  export PYTHONPATH=/tmp/site:$PWD/src
  mkdir -p /tmp/bin
  printf '#!/bin/sh\nexec python3 -c "import sys; from kinetix_cli.cli.app import main; sys.argv[0] = \\"kinetix\\"; main()" "$@"\n' >/tmp/bin/kinetix
  chmod +x /tmp/bin/kinetix
  kinetix=/tmp/bin/kinetix python=python3
  transformer=(--size m --envs 32768 --steps 64 --epochs 8 --minibatches 32 --width 128 --layers 5 --min-time 2)
  rel=(--size s --envs 4096 --steps 32 --epochs 4 --minibatches 4 --width 64 --layers 3 --min-time 2)
  sfl=(--set ppo.num_envs=4096 --set ppo.total_timesteps=3145728)  # 24 updates of 4,096 x 32
fi
export PYTHONUNBUFFERED=1
{ date -u; nvidia-smi -L 2>/dev/null; $python -c "import sys, jax; print(sys.version.split()[0], 'jax', jax.__version__, jax.devices())"
  git log -1 --format=%h 2>/dev/null; } >"$out/breakdown.log" 2>&1

# Each step has a bound, so that the call ends within its 600 s whatever a step takes (what it wrote comes back).
# (--score-levels 0: the breakdown's SFL row, added after this call was written, would add its compile to the
# bounds; step 2's runs measure SFL's share.)
timeout 200 "$kinetix" bench train --models transformer "${transformer[@]}" --breakdown --score-levels 0 \
  --json "$out/breakdown-transformer.json" 2>&1 | tee -a "$out/breakdown.log"
timeout 100 "$kinetix" bench train --models rel-mlp "${rel[@]}" --breakdown --score-levels 0 \
  --json "$out/breakdown-rel-mlp.json" 2>&1 | tee -a "$out/breakdown.log"

rm -rf /tmp/kc /tmp/sfl-*
declare -A bound=([cold]=150 [cached]=60)
for side in cold cached; do
  start=$(date +%s.%N)
  KINETIX_COMPILE_CACHE=/tmp/kc timeout ${bound[$side]} "$kinetix" pretrain --config experiments/general.yaml \
    --run-dir /tmp/sfl-$side --set curriculum.refresh_every=4 --set run.eval_every=0 --set run.checkpoint_every=0 "${sfl[@]}" 2>&1 | tail -3
  echo "$side $(python3 -c "import time; print(round(time.time() - $start, 1))")" | tee -a "$out/walls.txt"
  cp /tmp/sfl-$side/metrics.jsonl "$out/metrics-$side.jsonl"
done
du -sh /tmp/kc | tee -a "$out/walls.txt"
tar -czf "$out/compile-cache.tar.gz" -C /tmp kc  # for a later loan to carry (comes back if at most 16 MiB)
$python "$here/summary.py" "$out" | tee "$out/summary.txt"
