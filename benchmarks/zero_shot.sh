#!/usr/bin/env bash
# Zero-shot evaluation of a benchmark run's final policy: ATTEMPTS (20) sampled episodes per level of every suite,
# evaluation seed 1000, written to RUN/eval.json (curricula_summary.py reads it).
#
#   benchmarks/zero_shot.sh RUN SUITE...
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 RUN SUITE..." >&2
  exit 2
fi
run=$1
shift
levels=()
for suite in "$@"; do levels+=(--levels "$suite"); done
"${KINETIX:-.venv/bin/kinetix}" eval "$run" "${levels[@]}" --attempts "${ATTEMPTS:-20}" --seed 1000 --json "$run/eval.json"
