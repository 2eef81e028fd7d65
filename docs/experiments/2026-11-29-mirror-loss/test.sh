#!/usr/bin/env bash
# The test column (PLAN.md's rule, last sentence), read once after the decision: both arms' runs on the paper's 74
# levels at evaluation seeds 1000 and 1001. Run from the repository root after runs.sh. Resumable.
set -euo pipefail
out=docs/experiments/2026-11-29-mirror-loss
kinetix=.venv/bin/kinetix
for seed in 0 1 2; do
  for pair in "Y runs/mirror-loss/Y-$seed" "plain runs/batch-scale/minutes-256-$seed"; do
    set -- $pair
    for eval_seed in 1000 1001; do
      record=$out/test-$1-$seed-$eval_seed.json
      [ -f "$record" ] || $kinetix eval "$2" --levels test --attempts 50 --seed $eval_seed --json "$record" >/dev/null
    done
  done
  echo "seed $seed done"
done
