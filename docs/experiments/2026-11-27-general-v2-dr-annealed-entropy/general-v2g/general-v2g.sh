#!/usr/bin/env bash
# general v2 seventh candidate (2026-11-27): candidate B's recipe (general-s v2, then fresh l levels with SFL) with
# the learning rate annealed to 0 over 8M env steps (about what candidate B's seed 1 got in 60 minutes, partly under
# load; unloaded this run got there in 44), capped at 60 minutes; the fourth candidate annealed too but mixed in
# s-like levels. One seed (0).
set -euo pipefail
run=runs/general-v2g
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir $run \
  --set env.size=l --set run.minutes=60 --set ppo.total_timesteps=8000000 --set ppo.anneal_lr=true \
  --set run.init_from=general-s \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
  --set run.seed=0 --resume
.venv/bin/kinetix eval $run --levels .cache/reference-levels/s --levels .cache/reference-levels/m \
  --levels .cache/reference-levels/l --attempts 50 --seed 1000 --json $run/eval-1000.json
