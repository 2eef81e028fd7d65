#!/usr/bin/env bash
# issue 25: fine-tuning general-s v2 vs scratch, 3 seeds, the demo's 200K steps, entropy bonus 0.05 -> 0.01 (v1's
# fine-tuning recipe) in both arms; the scratch arm trains general-s v2's network (rel-mlp 64, masking)
set -euo pipefail
SEEDS="0 1 2" EVAL_EVERY=25 \
  SETS="ppo.ent_coef=0.05 ppo.ent_coef_end=0.01 model.name=rel-mlp model.width=64 model.mask_unused_actions=true" \
  benchmarks/finetune_vs_scratch.sh general-s 200000 runs/ft-v2 \
  levels/s/aim-then-fire.json levels/s/rocket-car-jump.json levels/s/pad-to-pad.json levels/s/jet-ball-hop.json \
  .cache/reference-levels/s/h1_thrust_over_ball.json .cache/reference-levels/s/h3_point_the_thruster.json
