#!/bin/bash
# Why the general recipe's plain update (0.63 s on the seventh session's VM, 2 devices) is slower than the
# benchmark's (0.50 s at the same network and batch): the recipe, then without SFL, then also without fresh levels
# (a generated pool of 1,024 held on the device), 128 updates each, default devices, one process each, alone.
# The median of the updates without SFL scoring, from each run's metrics.jsonl (summary.py).
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/recipe-gap
OUT=/tmp/recipe-gap
rm -rf $OUT && mkdir -p $OUT
COMMON="--config experiments/general.yaml --set ppo.total_timesteps=1048576 --set run.eval_every=0 --set run.checkpoint_every=0"
for variant in sfl-fresh dr-fresh dr-pool; do
  case $variant in
    sfl-fresh) SET="" ;;
    dr-fresh) SET="--set curriculum.name=dr" ;;
    dr-pool) SET="--set curriculum.name=dr --set levels.source=generated" ;;
  esac
  echo "== $variant $(date -u +%T)"
  .venv/bin/kinetix pretrain $COMMON $SET --run-dir $OUT/$variant 2>&1 | tail -1
  cp $OUT/$variant/metrics.jsonl $HERE/metrics-$variant.jsonl
done
echo "== done $(date -u +%T)"
