#!/usr/bin/env bash
# issue 25, demo rework screen: m/l hand-made levels where general-s v2 scores 5-10% zero-shot; fine-tune (entropy 0.05 -> 0.01) vs scratch (same network), 200K steps, seed 0
set -euo pipefail
SEEDS=0 EVAL_EVERY=25 \
  SETS="ppo.ent_coef=0.05 ppo.ent_coef_end=0.01 model.name=rel-mlp model.width=64 model.mask_unused_actions=true" \
  benchmarks/finetune_vs_scratch.sh general-s 200000 runs/demo-ml \
  levels/m/tilt-under-ceiling.json levels/m/ledge-leap-left.json levels/m/two-link-reach.json levels/l/maze-thruster-ball.json
