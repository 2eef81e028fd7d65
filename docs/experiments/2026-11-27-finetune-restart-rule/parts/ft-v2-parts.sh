#!/usr/bin/env bash
# issue 25: fine-tuning arms that start parts of general-s v2 afresh. ARM=critic: the critic (MLP and output layer)
# initialised anew, actor and shared features loaded (run.fresh_critic=true); ARM=features: actor output layer and
# critic anew, only the shared features (entity encoders) loaded (run.fresh_policy_head=true run.fresh_critic=true).
# Otherwise the finetuned arm of benchmarks/finetune-v2-cpu-2026-11-26/ft-v2.sh and
# benchmarks/demo-level-cpu-2026-11-27/demo-two-link.sh: 200K steps, entropy 0.05 -> 0.01, seeds 0-2, 50 attempts at
# evaluation seed 1000; the scratch and plain fine-tuned arms are those runs' (same settings and seeds).
#   ARM=critic SEEDS="0 1 2" LEVELS="levels/s/rocket-car-jump.json" benchmarks/finetune-v2-parts-cpu-2026-11-27/ft-v2-parts.sh
set -euo pipefail
arm=${ARM:?ARM=critic or ARM=features}
case $arm in
  critic) sets=(--set run.fresh_critic=true) ;;
  features) sets=(--set run.fresh_policy_head=true --set run.fresh_critic=true) ;;
  *) echo "ARM: critic or features, not $arm" >&2; exit 2 ;;
esac
out=${OUT:-runs/ft-v2-parts}
levels=${LEVELS:-levels/s/rocket-car-jump.json .cache/reference-levels/s/h1_thrust_over_ball.json \
levels/m/two-link-reach.json levels/s/pad-to-pad.json .cache/reference-levels/s/h3_point_the_thruster.json \
levels/s/jet-ball-hop.json}
for level in $levels; do
  name=$(basename "$level" .json)
  for seed in ${SEEDS:-0 1 2}; do
    dir=$out/$name/$arm-$seed
    [ -f "$dir/eval.json" ] && continue
    rm -rf "$dir"
    .venv/bin/kinetix finetune "$level" --from general-s --run-dir "$dir" --config experiments/cpu-small.yaml \
      --set ppo.total_timesteps=200000 --set run.seed=$seed --set run.eval_every=25 \
      --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01 "${sets[@]}"
    .venv/bin/kinetix eval "$dir" --levels "$level" --attempts 50 --seed 1000 --json "$dir/eval.json"
  done
done
