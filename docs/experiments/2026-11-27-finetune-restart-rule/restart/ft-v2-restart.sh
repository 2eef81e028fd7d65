#!/usr/bin/env bash
# issue 25: fine-tuning general-s v2 with run.restart_unsolved_after=25 (if the first 25 updates, 51,200 of the
# 200K steps, solve no training episode, start again from the loaded features alone); otherwise the finetuned arm of
# benchmarks/finetune-v2-cpu-2026-11-26/ft-v2.sh and benchmarks/demo-level-cpu-2026-11-27/demo-two-link.sh: 200K
# steps, entropy 0.05 -> 0.01, 50 attempts at evaluation seed 1000. Runs that do not restart are the plain
# fine-tuned runs of the same seed, step for step.
set -euo pipefail
out=${OUT:-runs/ft-v2-restart}
levels=${LEVELS:-levels/s/rocket-car-jump.json levels/m/two-link-reach.json \
.cache/reference-levels/s/h1_thrust_over_ball.json levels/s/pad-to-pad.json \
.cache/reference-levels/s/h3_point_the_thruster.json levels/s/jet-ball-hop.json levels/s/aim-then-fire.json}
for level in $levels; do
  name=$(basename "$level" .json)
  for seed in ${SEEDS:-0 1 2}; do
    dir=$out/$name/restart-$seed
    [ -f "$dir/eval.json" ] && continue
    rm -rf "$dir"
    .venv/bin/kinetix finetune "$level" --from general-s --run-dir "$dir" --config experiments/cpu-small.yaml \
      --set ppo.total_timesteps=200000 --set run.seed=$seed --set run.eval_every=25 \
      --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01 --set run.restart_unsolved_after=25
    .venv/bin/kinetix eval "$dir" --levels "$level" --attempts 50 --seed 1000 --json "$dir/eval.json"
  done
done
