#!/bin/bash
# Issue 70's 16K-step run of the shipped recipe, three times per tree in new processes (first, repeat, repeat), each
# tree with its own empty cache folder, interleaved: before-1, start-1, after-1, before-2, ..., each alone. Trees
# (worktrees on PYTHONPATH): before = 11c143b (as issue 70 found it), start = $1 (this session's start), after = $2.
# Output: repeat.txt next to this script.
set -uo pipefail
cd "$(dirname "$0")/../../../.."
HERE=docs/experiments/2026-12-05-learner-speed/repeat-again
OUT=/tmp/repeat-again; rm -rf $OUT; mkdir -p $OUT
declare -A COMMIT=([before]=11c143b [start]=${1:?start commit} [after]=${2:?after commit})
for side in before start after; do
  rm -rf /tmp/wt-ra-$side; git worktree prune; git worktree add -q --detach /tmp/wt-ra-$side ${COMMIT[$side]}
  echo "$side: $(git -C /tmp/wt-ra-$side rev-parse --short HEAD)" | tee -a $HERE/repeat.txt
done
RUN="pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0"
for round in 1 2 3; do
  for side in before start after; do
    start=$(date +%s.%N)
    PYTHONPATH=/tmp/wt-ra-$side/src KINETIX_COMPILE_CACHE=$OUT/cache-$side .venv/bin/kinetix $RUN \
      --run-dir $OUT/run-$side-$round > $OUT/log-$side-$round.txt 2>&1
    rc=$?; end=$(date +%s.%N)
    printf "%-6s %d rc %d %6.1f s  %s\n" $side $round $rc "$(echo "$end - $start" | bc)" "$(date -u +%T)" \
      | tee -a $HERE/repeat.txt
  done
done
for side in before start after; do git worktree remove --force /tmp/wt-ra-$side; done
