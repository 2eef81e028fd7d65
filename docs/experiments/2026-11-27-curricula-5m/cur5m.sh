#!/usr/bin/env bash
# issue 25: DR vs SFL vs PLR (positive value loss) at 5M env steps, the v2 recipe (experiments/general.yaml), size s,
# 50 attempts per level; one seed of each curriculum at a time so that a cut-off run still gives whole seeds.
set -euo pipefail
while pgrep -f "runs/after-ft[0-9]*.sh" > /dev/null; do sleep 15; done
for seed in ${SEED_LIST:-0 1 2}; do
  SEEDS=$seed CONFIG=experiments/general.yaml CURRICULA="dr sfl plr" ATTEMPTS=50 SETS="curriculum.plr_score=pvl" \
    benchmarks/curricula.sh 5000000 runs/cur5m-s
done
