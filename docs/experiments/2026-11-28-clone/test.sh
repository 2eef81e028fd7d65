#!/usr/bin/env bash
# The test columns (PLAN.md's rule, last sentence), read once after the decision: every arm's runs on the paper's 74
# levels at evaluation seeds 1000 and 1001. Run from the repository root after runs.sh has finished. Resumable.
set -euo pipefail
out=docs/experiments/2026-11-28-clone
kinetix=.venv/bin/kinetix
for run in runs/clone/[PCL]-[012]; do
  for seed in 1000 1001; do
    record=$out/test-$(basename "$run")-$seed.json
    [ -f "$record" ] || $kinetix eval "$run" --levels test --attempts 50 --seed $seed --json "$record" >/dev/null
  done
  echo "$run done"
done
