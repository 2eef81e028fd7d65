#!/usr/bin/env bash
# The blends of PLAN.md, each with its zero-shot validation; run from the repository root, alone on the machine, after
# the second round's D runs (runs/agents-v4-round2/D-{0,1,2}; from a fresh clone: RECIPES=D bash
# docs/experiments/2026-11-29-agents-v4-round2/runs.sh). Resumable: a written record is not redone.
set -euo pipefail
out=docs/experiments/2026-11-29-agents-v4-round3
runs=runs/agents-v4-round3
kinetix=.venv/bin/kinetix
for recipe in E F; do
  case $recipe in
    E) base=general-s@2 ;;
    F) base=general@3 ;;
  esac
  for seed in 0 1 2; do
    blend=$runs/$recipe-$seed
    [ -f "$blend/agent.json" ] || $kinetix agents blend "runs/agents-v4-round2/D-$seed" "$base" -o "$blend" \
      --name general --version 4 >"$out/blend-$recipe-$seed.log" 2>&1
    [ -f "$out/zero-shot-$recipe-$seed.json" ] || /usr/bin/time -f "%e s wall" -o "$out/zero-shot-$recipe-$seed.time" \
      $kinetix validation run "$blend" --finetune-seeds '' --json "$out/zero-shot-$recipe-$seed.json" \
      >"$out/zero-shot-$recipe-$seed.log" 2>&1
    echo "$recipe seed $seed done"
  done
done
python docs/experiments/2026-11-28-agents-v4/decide.py "$out" E F \
  general-m=v3:docs/experiments/2026-11-29-agents-v4-round2/zero-shot-D-2.json >"$out/decide.txt"
