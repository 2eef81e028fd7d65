#!/usr/bin/env bash
# Lever 4 (left-right symmetry) on the validation suite, as PLAN.md lists; run from the repository root.
set -euo pipefail
out=docs/experiments/2026-11-28-mirror
kinetix=.venv/bin/kinetix
[ -d runs/validation-mirror ] || $kinetix levels mirror validation -o runs/validation-mirror
run() {  # name agent seed extra...
  local name=$1 agent=$2 seed=$3; shift 3
  [ -f "$out/$name.json" ] || $kinetix eval "$agent" --attempts 50 --seed "$seed" --json "$out/$name.json" "$@" >/dev/null
  echo "$name done"
}
for seed in 1000 1001; do
  run general-plain-$seed general $seed --levels validation
  run general-mirrorimage-$seed general $seed --levels runs/validation-mirror
  for mode in mean geometric value; do
    run general-$mode-$seed general $seed --levels validation --mirror $mode
  done
done
for agent in general-s general-m general-l; do
  run $agent-plain-1000 $agent 1000 --levels validation
  run $agent-mirrorimage-1000 $agent 1000 --levels runs/validation-mirror
done
