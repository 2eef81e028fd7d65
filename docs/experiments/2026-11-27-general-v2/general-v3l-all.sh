#!/usr/bin/env bash
# The order these ran in (after temper-evals.sh): the held-out evaluations of the other two 400-update seeds of
# general v1's recipe, then general-v3l.sh for training seeds 1, 2, 3. Needs runs/heldout (heldout.sh) and
# runs/general-v2n-seed{1,3} (benchmarks/general-v2n-cpu-2026-11-27/general-v2n.sh).
set -euo pipefail
cd "$(dirname "$0")/../.."
k=.venv/bin/kinetix
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for s in 1 3; do $k eval runs/general-v2n-seed$s "${held[@]}" --attempts 20 --seed 2000 --json runs/general-v2n-seed$s-heldout.json; done
for s in 1 2 3; do bash benchmarks/general-v3-cpu-2026-11-27/general-v3l.sh $s; done
for f in general-v3b general-v3c general-v3c-confirm; do bash benchmarks/general-v3-cpu-2026-11-27/$f.sh; done
