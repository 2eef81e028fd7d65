#!/usr/bin/env bash
# Rule 5 of PLAN.md, read once after the decision (decide.txt committed) and deciding nothing: every copy (1-4 hours,
# seeds 20-22) on the test suite (the paper's 74 levels), 50 attempts, evaluation seed 1000. Run from the checkout's
# root after `make reference-levels`: bash docs/experiments/2026-11-30-agents-v4-round7/test.sh
set -euo pipefail
out=docs/experiments/2026-11-30-agents-v4-round7
[ -f "$out/decide.txt" ] || { echo "$out/decide.txt: missing; the test is read after the decision" >&2; exit 2; }
for seed in 20 21 22; do
  for minutes in 60 120 180 240; do
    name=K$minutes-$seed
    [ -f "$out/test-$name-1000.json" ] || .venv/bin/kinetix eval "runs/agents-v4-round7/K-$seed@$minutes" \
      --levels test --attempts 50 --seed 1000 --json "$out/test-$name-1000.json" >"$out/test-$name-1000.log" 2>&1
  done
done
