#!/usr/bin/env bash
# The equivariant arm as PLAN.md lists; run from the repository root after ../2026-11-28-batch-scale/equal-steps.sh.
set -euo pipefail
out=docs/experiments/2026-11-28-mirror-trained
base=docs/experiments/2026-11-28-batch-scale
kinetix=.venv/bin/kinetix
[ -d runs/validation-mirror ] || $kinetix levels mirror validation -o runs/validation-mirror
for seed in 0 1 2; do
  run=runs/mirror-trained/geometric-$seed
  if [ ! -f "$run/done" ]; then
    rm -rf "$run"
    /usr/bin/time -f "%e s wall" -o "$out/geometric-$seed.time" $kinetix pretrain --config experiments/general.yaml \
      --run-dir "$run" --set run.seed=$seed --set model.mirror=geometric --set ppo.total_timesteps=3_000_000 \
      --set run.eval_every=0 >"$out/geometric-$seed.log" 2>&1
    touch "$run/done"
  fi
  [ -f "$out/geometric-$seed.json" ] || $kinetix eval "$run" --levels validation --attempts 50 --seed 1000 \
    --json "$out/geometric-$seed.json" >/dev/null
  [ -f "$out/plain-$seed-mirrorimage.json" ] || $kinetix eval runs/batch-scale/steps-256-$seed \
    --levels runs/validation-mirror --attempts 50 --seed 1000 --json "$out/plain-$seed-mirrorimage.json" >/dev/null
  echo "seed $seed done"
done
