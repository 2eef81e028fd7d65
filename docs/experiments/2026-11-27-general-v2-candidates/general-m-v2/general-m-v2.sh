#!/usr/bin/env bash
# general-m v2 candidate (2026-11-27): general-s v2 (58 min of training at size s) trained on for 40 minutes (first started with 60, stopped at update ~130 and resumed with 40 to finish within the session) on
# fresh m levels with the v2 recipe (experiments/general.yaml): the whole agent within 2 hours of training;
# evaluated in-run on the paper's m levels with 10 attempts. Resume: add --resume.
set -euo pipefail
.venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir runs/general-m-v2 \
  --set env.size=m --set run.minutes=40 --set ppo.total_timesteps=48000000 \
  --set run.init_from=general-s \
  --set run.eval_every=400 --set run.eval_attempts=10 \
  --set 'run.eval_levels=[.cache/reference-levels/m]' \
  --set run.seed=0 --resume
