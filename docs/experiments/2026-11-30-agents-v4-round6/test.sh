#!/usr/bin/env bash
# Step 4 of PLAN.md, read once after the decision (decide.txt) and deciding nothing: every run's final checkpoint on
# the test suite (the paper's 74 levels), 50 attempts, evaluation seed 1000. Run from the checkout's root after `make
# reference-levels`: bash docs/experiments/2026-11-30-agents-v4-round6/test.sh
set -euo pipefail
out=docs/experiments/2026-11-30-agents-v4-round6
for seed in 0 1 2; do
  [ -f "$out/test-I-$seed-1000.json" ] || .venv/bin/kinetix eval "runs/agents-v4-round6/I-$seed" \
    --levels test --attempts 50 --seed 1000 --json "$out/test-I-$seed-1000.json" >"$out/test-I-$seed-1000.log" 2>&1
done
