#!/usr/bin/env bash
# Rule 3 of PLAN.md: the full validation (zero-shot and fine-tuning on the two levels, seeds 0-2) of each candidate
# decide.txt names. Run from the checkout's root: bash docs/experiments/2026-11-29-agents-v4-round3/full.sh E-1
set -euo pipefail
out=docs/experiments/2026-11-29-agents-v4-round3
for blend in "$@"; do
  /usr/bin/time -f "%e s wall" -o "$out/validation-$blend.time" .venv/bin/kinetix validation run \
    "runs/agents-v4-round3/$blend" --json "$out/validation-$blend.json" >"$out/validation-$blend.log" 2>&1
done
