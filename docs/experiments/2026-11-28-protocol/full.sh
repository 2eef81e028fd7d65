#!/usr/bin/env bash
# Rule 2 of PLAN.md: the full validation (zero-shot and fine-tuning, seeds 0 1 2) of the four versions rule 1 chose
# (decide.txt). Run from the checkout's root: bash docs/experiments/2026-11-28-protocol/full.sh
set -euo pipefail
out=docs/experiments/2026-11-28-protocol
for agent in general-s@2 general-m@2 general-l@2 general@3; do
  .venv/bin/kinetix validation run "$agent" --json "$out/validation-${agent/@/-v}.json" > "$out/validation-${agent/@/-v}.log" 2>&1
done
