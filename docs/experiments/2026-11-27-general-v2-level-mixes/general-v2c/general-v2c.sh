#!/usr/bin/env bash
# general v2 candidate C (2026-11-27): general-s v2 (58 min of training at size s) trained on for at most 62 minutes
# at size m on fresh levels drawn half like s and half like m (levels.fresh_like), learning rate annealed to 0 over
# 16M env steps; the whole agent within 2 hours of training. In-run evaluation on the paper's s and m levels.
set -euo pipefail
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir runs/general-v2c \
  --set env.size=m --set 'levels.fresh_like=[s,m]' \
  --set run.minutes=62 --set ppo.total_timesteps=16000000 --set ppo.anneal_lr=true \
  --set run.init_from=general-s \
  --set run.eval_every=500 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m]' \
  --set run.seed=0 --resume
