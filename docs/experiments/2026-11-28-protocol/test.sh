#!/usr/bin/env bash
# Rule 3 of PLAN.md: each chosen version on the test suite (the paper's 74 levels) once, after the choice: 50 attempts,
# evaluation seeds 1000 and 1001. Run from the checkout's root after `make reference-levels`:
# bash docs/experiments/2026-11-28-protocol/test.sh
set -euo pipefail
out=docs/experiments/2026-11-28-protocol
for agent in general-s@2 general-m@2 general-l@2 general@3; do
  for seed in 1000 1001; do
    .venv/bin/kinetix eval "$agent" --levels test --attempts 50 --seed "$seed" --json "$out/test-${agent/@/-v}-$seed.json" \
      > "$out/test-${agent/@/-v}-$seed.log" 2>&1
  done
done
