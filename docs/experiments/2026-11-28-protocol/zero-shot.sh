#!/usr/bin/env bash
# Rule 1 of PLAN.md: every shipped version's zero-shot part of the validation suite (50 attempts, evaluation seed
# 1000). Run from the checkout's root: bash docs/experiments/2026-11-28-protocol/zero-shot.sh
set -euo pipefail
out=docs/experiments/2026-11-28-protocol
for agent in general-s@1 general-s@2 general-s@3 general-m@1 general-m@2 general-l@1 general-l@2 general@1 general@2 \
  general@3; do
  .venv/bin/kinetix validation run "$agent" --finetune-seeds '' --json "$out/zero-shot-${agent/@/-v}.json" \
    > "$out/zero-shot-${agent/@/-v}.log" 2>&1
done
