#!/bin/bash
OUT=/tmp/cache-repeat
RUN=(pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0)
one() { local tree=$1 tag=$2 var=$3 cache=$4; rm -rf $OUT/run-$tag; local s=$(date +%s.%N)
 (cd $tree && env $var=$OUT/$cache .venv/bin/kinetix "${RUN[@]}" --run-dir $OUT/run-$tag > $OUT/log-$tag.txt 2>&1); local rc=$?
 printf "%-9s rc %d %6.1f s\n" $tag $rc $(echo "$(date +%s.%N) - $s" | bc); }
one /work/base-clone before-3 JAX_COMPILATION_CACHE_DIR cache-before
one /work/main after-3 KINETIX_COMPILE_CACHE cache-after
one /work/main after-4 KINETIX_COMPILE_CACHE cache-after
one /work/base-clone before-4 JAX_COMPILATION_CACHE_DIR cache-before
