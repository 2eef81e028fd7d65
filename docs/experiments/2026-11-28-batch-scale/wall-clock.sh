#!/usr/bin/env bash
# Part 2 (equal wall-clock, PLAN.md's amendment) of the batch-scale study, and lever 4's equal-wall-clock arm
# (../2026-11-28-mirror-trained/PLAN.md): every arm 10 minutes of training, seeds 0-2, one run at a time with nothing
# else running. Run from the repository root; ARMS="256 1024 4096 mirror" by default. Resumable.
set -euo pipefail
out=docs/experiments/2026-11-28-batch-scale
kinetix=.venv/bin/kinetix
for arm in ${ARMS:-256 1024 4096 mirror}; do
  for seed in 0 1 2; do
    run=runs/batch-scale/minutes-$arm-$seed
    case $arm in
      mirror) extra=(--set model.mirror=geometric) ;;
      *) extra=(--set ppo.num_envs=$arm --set curriculum.refresh_every=$((64 * 256 / arm))) ;;
    esac
    if [ ! -f "$run/done" ]; then
      rm -rf "$run"
      /usr/bin/time -f "%e s wall" -o "$out/minutes-$arm-$seed.time" $kinetix pretrain --config experiments/general.yaml \
        --run-dir "$run" --set run.seed=$seed "${extra[@]}" --set run.minutes=10 \
        --set ppo.total_timesteps=100_000_000 --set run.eval_every=0 >"$out/minutes-$arm-$seed.log" 2>&1
      touch "$run/done"
    fi
    [ -f "$out/minutes-$arm-$seed.json" ] || $kinetix eval "$run" --levels validation --attempts 50 --seed 1000 \
      --json "$out/minutes-$arm-$seed.json" >/dev/null
    echo "minutes $arm seed $seed done"
  done
done
