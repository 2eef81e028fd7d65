#!/bin/bash
# The recipe's first 128 updates at seed 2 as the learning table's after run had them (run.minutes set,
# checkpoint every 768) and without the budget, alternating, alone: does the budget cost time per update?
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/recipe-gap
OUT=/tmp/recipe-gap
COMMON="--config experiments/general.yaml --set ppo.total_timesteps=1048576 --set run.eval_every=0 --set run.seed=2"
for round in 1 2; do
  for variant in budget plain; do
    case $variant in
      budget) SET="--set run.minutes=30 --set run.checkpoint_every=768" ;;
      plain) SET="--set run.checkpoint_every=0" ;;
    esac
    echo "== $variant $round $(date -u +%T)"
    rm -rf $OUT/$variant-$round
    .venv/bin/kinetix pretrain $COMMON $SET --run-dir $OUT/$variant-$round > $OUT/$variant-$round.log 2>&1
    tail -1 $OUT/$variant-$round.log
    cp $OUT/$variant-$round/metrics.jsonl $HERE/metrics-seed2-$variant-$round.jsonl
  done
done
