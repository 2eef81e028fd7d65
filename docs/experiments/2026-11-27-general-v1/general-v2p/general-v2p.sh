#!/usr/bin/env bash
# general v2 candidate (2026-11-27): the 400-update runs at m (general-v2n.sh) with the learning rate at 1e-4
# instead of 3e-4: does a smaller step keep what general-s v2 plays at s (seeds 1 and 3 of general-v2n lost h7)
# while it learns m? Usage: general-v2p.sh SEED
set -euo pipefail
seed=$1
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir runs/general-v2p-seed$seed \
  --set env.size=m --set ppo.total_timesteps=3276800 --set ppo.lr=1e-4 \
  --set run.init_from=general-s \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
  --set run.seed=$seed --resume
