#!/usr/bin/env bash
# general v2 candidate E (2026-11-27): the fourth candidate's level mix with the second candidate's constant learning
# rate. general-s v2 (58 min of training at size s) trained on for at most 60 minutes at size l on fresh levels drawn
# one third like s and two thirds like l (levels.fresh_like), lr 3e-4 constant (candidates C and D annealed it, B did
# not); the whole agent within 2 hours of training. In-run evaluation on all 74 paper levels with 10 attempts.
set -euo pipefail
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir runs/general-v2e \
  --set env.size=l --set 'levels.fresh_like=[s,l,l]' \
  --set run.minutes=60 --set ppo.total_timesteps=48000000 \
  --set run.init_from=general-s \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
  --set run.seed=0 --resume
