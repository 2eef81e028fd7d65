#!/usr/bin/env bash
# issue 25: a third arm for the fine-tuning table: general-s v2 with a fresh policy head (run.fresh_policy_head),
# otherwise the finetuned arm of runs/ft-v2.sh (200K steps, entropy 0.05 -> 0.01, seeds 0-2, 50 attempts seed 1000)
set -euo pipefail
while pgrep -f runs/ft-v2.sh > /dev/null; do sleep 20; done
for level in levels/s/aim-then-fire.json levels/s/rocket-car-jump.json levels/s/pad-to-pad.json levels/s/jet-ball-hop.json \
  .cache/reference-levels/s/h1_thrust_over_ball.json .cache/reference-levels/s/h3_point_the_thruster.json; do
  name=$(basename "$level" .json)
  for seed in 0 1 2; do
    dir=runs/ft-v2/$name/fresh-head-$seed
    [ -f "$dir/eval.json" ] && continue
    rm -rf "$dir"
    .venv/bin/kinetix finetune "$level" --from general-s --run-dir "$dir" --config experiments/cpu-small.yaml \
      --set ppo.total_timesteps=200000 --set run.seed=$seed --set run.eval_every=25 \
      --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01 --set run.fresh_policy_head=true
    .venv/bin/kinetix eval "$dir" --levels "$level" --attempts 50 --seed 1000 --json "$dir/eval.json"
  done
done
