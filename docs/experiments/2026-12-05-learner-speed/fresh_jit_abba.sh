#!/bin/bash
# The cached repeat of the 16K-step run, with fresh_levels traced twice (BEFORE_SRC: src of ea83a2f) and once (this
# checkout's src), in the order before, after, after, before; each tree's cache written by a first run of its own.
set -u
BEFORE_SRC=${BEFORE_SRC:?src folder of ea83a2f}
OUT=${OUT:-/tmp/fresh-abba}
mkdir -p "$OUT"
RUN=(pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0)
one() {  # tag src
  rm -rf "$OUT/run-$1"
  local s=$(date +%s.%N)
  PYTHONPATH=$2 KINETIX_COMPILE_CACHE=$OUT/cache-${1%-*} .venv/bin/kinetix "${RUN[@]}" --run-dir "$OUT/run-$1" > "$OUT/log-$1.txt" 2>&1
  printf "%-9s rc %d %6.1f s\n" "$1" $? "$(echo "$(date +%s.%N) - $s" | bc)"
}
for tag in before-warm after-warm; do  # fill each cache (not timed for the table)
  [ -d "$OUT/cache-${tag%-*}" ] || one "$tag" "$([ "${tag%-*}" = before ] && echo "$BEFORE_SRC" || echo src)"
done
one before-1 "$BEFORE_SRC"; one after-1 src; one after-2 src; one before-2 "$BEFORE_SRC"
