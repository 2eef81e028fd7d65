#!/usr/bin/env bash
# PLAN.md's fourth seed: both arms at 3M env steps with training seed 3, run from the root of a fresh clone after
# `make test` (which builds .venv). Records land beside this file in that clone.
set -euo pipefail
out=docs/experiments/2026-11-28-mirror-trained
kinetix=.venv/bin/kinetix
for arm in plain geometric; do
  run=runs/mirror-trained/$arm-3
  case $arm in
    geometric) extra=(--set model.mirror=geometric) ;;
    *) extra=(--set ppo.num_envs=256 --set curriculum.refresh_every=64) ;;
  esac
  if [ ! -f "$run/done" ]; then
    rm -rf "$run"
    /usr/bin/time -f "%e s wall" -o "$out/$arm-3.time" $kinetix pretrain --config experiments/general.yaml \
      --run-dir "$run" --set run.seed=3 "${extra[@]}" --set ppo.total_timesteps=3_000_000 --set run.eval_every=0 \
      >"$out/$arm-3.log" 2>&1
    touch "$run/done"
  fi
  [ -f "$out/$arm-3.json" ] || $kinetix eval "$run" --levels validation --attempts 50 --seed 1000 \
    --json "$out/$arm-3.json" >/dev/null
  echo "$arm seed 3 done"
done
