#!/bin/bash
# README.md's run: for each XLA flag setting (base, nofusion, split1, or those given as arguments), an empty cache
# folder, then issue 70's 16K-step run three times in new processes (first, repeat, repeat), timed, each wrapped by
# probe.py (time reading JAX's cache and compiling); then the SFL update's cache entry's object count. Output:
# run.txt next to this script (appended); logs and caches in /tmp/load-flags.
cd "$(dirname "$0")/../../../.."
HERE=docs/experiments/2026-12-05-learner-speed/load-flags
RUN="pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0"
declare -A FLAGS=([base]="" [nofusion]="--xla_cpu_use_fusion_emitters=false"
  [split1]="--xla_cpu_parallel_codegen_split_count=1")
OUT=/tmp/load-flags; mkdir -p $OUT
for s in ${@:-base nofusion split1}; do
  rm -rf $OUT/cache-$s
  for i in 1 2 3; do
    start=$(date +%s.%N)
    XLA_FLAGS="${FLAGS[$s]}" KINETIX_COMPILE_CACHE=$OUT/cache-$s .venv/bin/python $HERE/probe.py $RUN \
      --run-dir $OUT/run-$s-$i > $OUT/log-$s-$i.txt 2>&1
    rc=$?; end=$(date +%s.%N)
    printf "%-9s %d rc %d %6.1f s %s | %s\n" $s $i $rc "$(echo "$end - $start" | bc)" "$(date -u +%T)" \
      "$(grep 'PROBE reads' $OUT/log-$s-$i.txt)" | tee -a $HERE/run.txt
  done
  f=$(ls -S $OUT/cache-$s/jit_sfl_update-*-cache 2>/dev/null | head -1)
  [ -n "$f" ] && .venv/bin/python -c "import zlib; d = zlib.decompress(open('$f', 'rb').read()); \
print('$s: SFL update entry', len(d), 'bytes,', d.count(b'\x7fELF'), 'objects')" | tee -a $HERE/run.txt
done
