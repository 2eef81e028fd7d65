#!/bin/bash
# Issue 70's 16K-step run of the shipped recipe, three times per side in new processes (first, repeat, repeat),
# each side with its own empty cache folder, interleaved, each alone. Sides: before = 11c143b, start = b8e380f,
# loads = $1 (default ec3ca13; each with ml_dtypes 0.7.0 first on PYTHONPATH, from /tmp/mld-0.7.0), after = $2
# (default ec3ca13) with the venv's ml_dtypes (0.6.0). Output: appended to repeat.txt next to this script.
set -uo pipefail
cd "$(dirname "$0")/../../../.."
HERE=docs/experiments/2026-12-05-learner-speed/repeat-loaded
OUT=/tmp/repeat-loaded; rm -rf $OUT; mkdir -p $OUT
[ -d /tmp/mld-0.7.0/ml_dtypes ] || .venv/bin/pip install -q --no-deps --target /tmp/mld-0.7.0 ml_dtypes==0.7.0
declare -A COMMIT=([before]=11c143b [start]=b8e380f [loads]=${1:-ec3ca13} [after]=${2:-ec3ca13})
declare -A EXTRA=([before]=/tmp/mld-0.7.0: [start]=/tmp/mld-0.7.0: [loads]=/tmp/mld-0.7.0: [after]=)
SIDES="before start loads after"
echo "--- $(date -u +%F\ %T) UTC" >> $HERE/repeat.txt
for side in $SIDES; do
  rm -rf /tmp/wt-rl-$side; git worktree prune; git worktree add -q --detach /tmp/wt-rl-$side ${COMMIT[$side]}
  echo "$side: $(git -C /tmp/wt-rl-$side rev-parse --short HEAD), PYTHONPATH ${EXTRA[$side]}/tmp/wt-rl-$side/src" \
    | tee -a $HERE/repeat.txt
done
RUN="pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0"
for round in 1 2 3; do
  for side in $SIDES; do
    start=$(date +%s.%N)
    PYTHONPATH=${EXTRA[$side]}/tmp/wt-rl-$side/src KINETIX_COMPILE_CACHE=$OUT/cache-$side .venv/bin/kinetix $RUN \
      --run-dir $OUT/run-$side-$round > $OUT/log-$side-$round.txt 2>&1
    rc=$?; end=$(date +%s.%N)
    printf "%-6s %d rc %d %6.1f s  %s\n" $side $round $rc "$(echo "$end - $start" | bc)" "$(date -u +%T)" \
      | tee -a $HERE/repeat.txt
  done
done
for side in $SIDES; do git worktree remove --force /tmp/wt-rl-$side; done
