#!/usr/bin/env bash
# issue 25, demo rework: two-link-reach (m; general-s v2 zero-shot 5%) seeds 1 and 2, as runs/demo-ml.sh
set -euo pipefail
SEEDS="1 2" EVAL_EVERY=25 \
  SETS="ppo.ent_coef=0.05 ppo.ent_coef_end=0.01 model.name=rel-mlp model.width=64 model.mask_unused_actions=true" \
  benchmarks/finetune_vs_scratch.sh general-s 200000 runs/demo-ml levels/m/two-link-reach.json
