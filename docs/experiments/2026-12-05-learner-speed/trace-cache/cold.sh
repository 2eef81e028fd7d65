#!/bin/bash
# The first (cold) run of repeat.sh's command with and without the trace cache, in the same code otherwise: the commit
# given as $1 (main before the trace cache) against $2 (with it), alternating A B A B, each with an empty cache
# folder of its own, each alone. Output: cold.txt next to this script.
set -uo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/trace-cache
OUT=/tmp/trace-cold; rm -rf $OUT; mkdir -p $OUT
for side in A B; do
  commit=$([ $side = A ] && echo ${1:?commit without} || echo ${2:?commit with})
  rm -rf /tmp/wt-cold-$side; git worktree prune; git worktree add -q --detach /tmp/wt-cold-$side $commit
  echo "$side: $(git -C /tmp/wt-cold-$side rev-parse --short HEAD)" | tee -a $HERE/cold.txt
done
RUN="pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0"
for tag in A-1 B-1 A-2 B-2; do
  side=${tag%-*}
  start=$(date +%s.%N)
  PYTHONPATH=/tmp/wt-cold-$side/src KINETIX_COMPILE_CACHE=$OUT/cache-$tag .venv/bin/kinetix $RUN \
    --run-dir $OUT/run-$tag > $OUT/log-$tag.txt 2>&1
  rc=$?; end=$(date +%s.%N)
  printf "%-4s rc %d %6.1f s  %s\n" $tag $rc $(echo "$end - $start" | bc) "$(date -u +%T)" | tee -a $HERE/cold.txt
done
