#!/usr/bin/env bash
# general v2 soup ingredient (2026-11-27): general-s v2 trained on for 25 minutes of training time at size m with the
# v2 recipe (SFL, constant lr), evaluated in-run on all 74 paper levels (10 attempts). Usage: general-v2m.sh SEED
# Run with seed 0 (9.4M env steps, update 1,152); seed 1 was started after it and stopped after two minutes, when
# seed 0's blend scored below the earlier ones (the 400-update runs, general-v2n, took its place).
set -euo pipefail
seed=$1
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir runs/general-v2m-seed$seed \
  --set env.size=m --set run.minutes=25 --set ppo.total_timesteps=48000000 \
  --set run.init_from=general-s \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
  --set run.seed=$seed --resume
