#!/bin/bash
# The issue's 16K-step run of the shipped recipe, twice per tree in new processes, each tree with its own empty cache
# folder; order before-1, after-1, before-2, after-2. Before: the source of 11c143b (PYTHONPATH); after: HEAD.
cd /work/main
OUT=/tmp/ab/repeat; rm -rf $OUT; mkdir -p $OUT
RUN="pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0"
for tag in before-1 after-1 before-2 after-2; do
  side=${tag%-*}; if [ $side = before ]; then PP=/tmp/wt-before/src; else PP=/work/main/src; fi
  start=$(date +%s.%N)
  PYTHONPATH=$PP KINETIX_COMPILE_CACHE=$OUT/cache-$side .venv/bin/kinetix $RUN --run-dir $OUT/run-$tag > $OUT/log-$tag.txt 2>&1
  rc=$?; end=$(date +%s.%N)
  printf "%-9s rc %d %6.1f s\n" $tag $rc $(echo "$end - $start" | bc)
done
