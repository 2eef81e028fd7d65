#!/usr/bin/env bash
# Rule 3 of PLAN.md: the full validation (zero-shot and fine-tuning on the two levels, seeds 0-2) of each candidate
# decide.txt names, by its copy. Run from the checkout's root:
#   bash docs/experiments/2026-11-30-agents-v4-round7/full.sh K-S@T
set -euo pipefail
out=docs/experiments/2026-11-30-agents-v4-round7
for copy in "$@"; do
  [ -d "runs/agents-v4-round7/$copy" ] || { echo "runs/agents-v4-round7/$copy: no such copy" >&2; exit 2; }
  /usr/bin/time -f "%e s wall" -o "$out/validation-$copy.time" .venv/bin/kinetix validation run \
    "runs/agents-v4-round7/$copy" --json "$out/validation-$copy.json" >"$out/validation-$copy.log" 2>&1
done
