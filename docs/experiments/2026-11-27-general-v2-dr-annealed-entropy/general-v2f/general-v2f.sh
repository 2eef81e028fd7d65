#!/usr/bin/env bash
# general v2 sixth candidate (2026-11-27): candidate B's recipe (general-s v2, then 60 min of training on fresh l
# levels, constant lr) with DR instead of SFL. Why: at 5M steps on s, DR matched SFL's mean with a fraction of its
# seed spread (curricula again, BENCHMARKS), and at l SFL's scoring takes about a third of the env steps, so DR
# trains more steps in the same minutes (measured: 10.8M, 1.3x candidate B's seed 1). Each seed evaluated on all 74
# paper levels with 50 attempts (eval seed 1000). Run with seed 0 only: its in-run evaluation fell at update 1,200
# and its training solve rate stayed flat (7-10%), so the second seed's hour went to the seventh candidate instead
# (SEEDS="0 1" runs both).
set -euo pipefail
for seed in ${SEEDS:-0}; do
  run=runs/general-v2f-seed$seed
  .venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir $run \
    --set env.size=l --set run.minutes=60 --set ppo.total_timesteps=48000000 \
    --set run.init_from=general-s --set curriculum.name=dr \
    --set run.eval_every=400 --set run.eval_attempts=10 \
    --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
    --set run.seed=$seed --resume
  .venv/bin/kinetix eval $run --levels .cache/reference-levels/s --levels .cache/reference-levels/m \
    --levels .cache/reference-levels/l --attempts 50 --seed 1000 --json $run/eval-1000.json
done
