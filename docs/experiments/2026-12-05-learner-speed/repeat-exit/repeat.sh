#!/bin/bash
# Issue 70's 16K-step run of the shipped recipe: a first run and four repeats per side in new processes, each side
# with its own empty cache folder, interleaved, each alone. before = 11c143b with ml_dtypes 0.7.0 first on
# PYTHONPATH (/tmp/mld-0.7.0), after = 6abf426 with the venv's (0.6.0). Output: appended to repeat.txt here.
set -uo pipefail
cd "$(dirname "$0")/../../../.."
HERE=docs/experiments/2026-12-05-learner-speed/repeat-exit
OUT=/tmp/repeat-exit; rm -rf $OUT; mkdir -p $OUT
[ -d /tmp/mld-0.7.0/ml_dtypes ] || .venv/bin/pip install -q --no-deps --target /tmp/mld-0.7.0 ml_dtypes==0.7.0
declare -A COMMIT=([before]=11c143b [after]=6abf426)
declare -A EXTRA=([before]=/tmp/mld-0.7.0: [after]=)
echo "--- $(date -u +%F\ %T) UTC" >> $HERE/repeat.txt
for side in before after; do
  rm -rf /tmp/wt-re-$side; git worktree prune; git worktree add -q --detach /tmp/wt-re-$side ${COMMIT[$side]}
  echo "$side: $(git -C /tmp/wt-re-$side rev-parse --short HEAD)" | tee -a $HERE/repeat.txt
done
RUN="pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0"
for round in 1 2 3 4 5; do
  for side in before after; do
    start=$(date +%s.%N)
    PYTHONPATH=${EXTRA[$side]}/tmp/wt-re-$side/src KINETIX_COMPILE_CACHE=$OUT/cache-$side .venv/bin/kinetix $RUN \
      --run-dir $OUT/run-$side-$round > $OUT/log-$side-$round.txt 2>&1
    rc=$?; end=$(date +%s.%N)
    printf "%-6s %d rc %d %6.1f s  %s\n" $side $round $rc "$(echo "$end - $start" | bc)" "$(date -u +%T)" \
      | tee -a $HERE/repeat.txt
  done
done
for side in before after; do git worktree remove --force /tmp/wt-re-$side; done
