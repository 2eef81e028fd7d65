#!/usr/bin/env bash
# Lever 3, part 1 (equal environment steps), as PLAN.md lists; run from the repository root.
set -euo pipefail
out=docs/experiments/2026-11-28-batch-scale
kinetix=.venv/bin/kinetix
for envs in ${ENVS:-256 1024 4096}; do
  for seed in 0 1 2; do
    run=runs/batch-scale/steps-$envs-$seed
    refresh=$((64 * 256 / envs))
    if [ ! -f "$run/done" ]; then
      rm -rf "$run"  # an interrupted run starts again
      /usr/bin/time -f "%e s wall" -o "$out/steps-$envs-$seed.time" $kinetix pretrain --config experiments/general.yaml \
        --run-dir "$run" --set run.seed=$seed --set ppo.num_envs=$envs --set curriculum.refresh_every=$refresh \
        --set ppo.total_timesteps=3_000_000 --set run.eval_every=0 >"$out/steps-$envs-$seed.log" 2>&1
      touch "$run/done"
    fi
    [ -f "$out/steps-$envs-$seed.json" ] || $kinetix eval "$run" --levels validation --attempts 50 --seed 1000 \
      --json "$out/steps-$envs-$seed.json" >/dev/null
    echo "steps $envs seed $seed done"
  done
done
