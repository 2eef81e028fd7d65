#!/usr/bin/env bash
# general v2 candidate (2026-11-27): general-s v2 trained on for 400 updates (3.3M env steps) at size m with
# the v2 recipe (SFL, constant lr). 400: where training at m peaked on the paper's m levels in two earlier runs
# (general-m v2 first candidate: 29.2% at update 400; general-v2m seed 0: s 39 / m 29.2 / l 9.8 at 400, falling
# after). Usage: general-v2n.sh SEED
set -euo pipefail
seed=$1
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir runs/general-v2n-seed$seed \
  --set env.size=m --set ppo.total_timesteps=3276800 \
  --set run.init_from=general-s \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
  --set run.seed=$seed --resume
