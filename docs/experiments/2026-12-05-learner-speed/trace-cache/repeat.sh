#!/bin/bash
# Issue 70's 16K-step run of the shipped recipe (two updates, SFL scoring 384 fresh levels before the first), three
# times per tree in new processes, each tree with its own empty cache folder, alternating: before-1, after-1,
# before-2, after-2, before-3, after-3, each alone. Before: the commit given as $1 (11c143b: as issue 70 found it);
# after: the commit given as $2. Each a worktree on PYTHONPATH. Output: repeat.txt next to this script.
set -uo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/trace-cache
OUT=/tmp/trace-repeat; rm -rf $OUT; mkdir -p $OUT
for side in before after; do
  commit=$([ $side = before ] && echo ${1:?before commit} || echo ${2:?after commit})
  rm -rf /tmp/wt-tc-$side; git worktree prune; git worktree add -q --detach /tmp/wt-tc-$side $commit
  echo "$side: $(git -C /tmp/wt-tc-$side rev-parse --short HEAD)" | tee -a $HERE/repeat.txt
done
RUN="pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0"
for tag in before-1 after-1 before-2 after-2 before-3 after-3; do
  side=${tag%-*}
  start=$(date +%s.%N)
  PYTHONPATH=/tmp/wt-tc-$side/src KINETIX_COMPILE_CACHE=$OUT/cache-$side .venv/bin/kinetix $RUN \
    --run-dir $OUT/run-$tag > $OUT/log-$tag.txt 2>&1
  rc=$?; end=$(date +%s.%N)
  printf "%-9s rc %d %6.1f s  %s\n" $tag $rc $(echo "$end - $start" | bc) "$(date -u +%T)" | tee -a $HERE/repeat.txt
done
for tag in after-1 after-2 after-3; do  # a run whose traces are read back computes what the traced one computed
  sed 's/"sps": [0-9.e+-]*, //' $OUT/run-$tag/metrics.jsonl > $OUT/metrics-$tag.txt
done
cmp -s $OUT/metrics-after-1.txt $OUT/metrics-after-2.txt && cmp -s $OUT/metrics-after-1.txt $OUT/metrics-after-3.txt \
  && echo "after's metrics: equal in all three runs but sps" | tee -a $HERE/repeat.txt \
  || echo "after's metrics: differ" | tee -a $HERE/repeat.txt
