#!/usr/bin/env bash
# general v2, a probe of the entropy finding, not a finished candidate (2026-11-27): the second candidate's recipe
# (general-s v2, then fresh l levels with SFL, constant lr) with the entropy weight at 0.001 instead of 0.01: does
# the entropy still rise at l, and how does update 400 compare? Stopped by hand after its update-400 evaluation
# (update 434; the session was ending); seed 0.
set -euo pipefail
run=runs/general-v2h
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir $run \
  --set env.size=l --set run.minutes=60 --set ppo.total_timesteps=48000000 --set ppo.ent_coef=0.001 \
  --set run.init_from=general-s \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/s,.cache/reference-levels/m,.cache/reference-levels/l]' \
  --set run.seed=0 --resume
