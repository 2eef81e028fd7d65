#!/usr/bin/env bash
# general v2 candidate B (2026-11-27): general-s v2 (58 min of training at size s) trained on for 60 more minutes on
# fresh l levels with the same recipe (experiments/general.yaml), so the whole agent stays within 2 hours of
# training; evaluated in-run on all 74 paper levels with 10 attempts. Resume: --resume --set run.minutes=...
set -euo pipefail
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir runs/general-v2b \
  --set env.size=l --set run.minutes=60 --set ppo.total_timesteps=48000000 \
  --set run.init_from=general-s \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
  --set run.seed=0 --resume
