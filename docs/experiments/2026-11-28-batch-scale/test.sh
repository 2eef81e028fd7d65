#!/usr/bin/env bash
# The test column (PLAN.md's last section), read once after part 2's decision: every run of both parts, and the
# mirror-trained study's geometric runs, on the paper's 74 levels. Run from the repository root. Resumable.
set -euo pipefail
out=docs/experiments/2026-11-28-batch-scale
kinetix=.venv/bin/kinetix
for run in runs/batch-scale/*-*-[012] runs/mirror-trained/geometric-[012]; do
  case $run in
    runs/mirror-trained/*) record=docs/experiments/2026-11-28-mirror-trained/test-$(basename "$run").json ;;
    *) record=$out/test-$(basename "$run").json ;;
  esac
  [ -f "$record" ] || $kinetix eval "$run" --levels test --attempts 50 --seed 1000 --json "$record" >/dev/null
  echo "$run done"
done
