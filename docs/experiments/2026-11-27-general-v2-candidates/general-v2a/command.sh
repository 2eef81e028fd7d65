#!/usr/bin/env bash
# general v2 candidate A (2026-11-26): the v2 recipe (experiments/general.yaml) on fresh l levels, as the paper's
# general agents train (random l levels; s and m scenes fit in l), for a training budget of run.minutes (95 min in the first session, 2026-11-27; resume with --resume --set run.minutes=... to extend); evaluated in-run
# on all 74 paper levels with 10 attempts
set -euo pipefail
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir runs/general-v2a \
  --set env.size=l --set run.minutes=95 --set ppo.total_timesteps=48000000 \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
  --set run.seed=0
