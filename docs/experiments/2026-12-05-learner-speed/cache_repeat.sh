#!/bin/bash
# The compile cache across processes: the same 16K-step run of the shipped recipe, run twice in new processes, each
# tree with its own empty cache folder, before (BEFORE: a checkout of aae514f with its .venv; its cache is JAX's
# JAX_COMPILATION_CACHE_DIR) and after (this checkout; KINETIX_COMPILE_CACHE). Order: before 1, after 1, before 2,
# after 2. Prints wall seconds per run; logs in $OUT.
set -u
BEFORE=${BEFORE:?a checkout of the code before, with .venv}
AFTER=${AFTER:-$(pwd)}
OUT=${OUT:-/tmp/cache-repeat}
rm -rf "$OUT" && mkdir -p "$OUT"
RUN=(pretrain --config experiments/general.yaml --set ppo.total_timesteps=16384 --set run.eval_every=0)
one() {  # tree tag variable
  local tree=$1 tag=$2 var=$3
  rm -rf "$OUT/run-$tag"
  local start=$(date +%s.%N)
  (cd "$tree" && env "$var=$OUT/cache-${tag%-*}" .venv/bin/kinetix "${RUN[@]}" --run-dir "$OUT/run-$tag" > "$OUT/log-$tag.txt" 2>&1)
  local rc=$?
  local end=$(date +%s.%N)
  printf "%-9s rc %d  %6.1f s  entries %s\n" "$tag" $rc "$(echo "$end - $start" | bc)" "$(ls "$OUT/cache-${tag%-*}" | grep -c -- '-cache$')"
}
one "$BEFORE" before-1 JAX_COMPILATION_CACHE_DIR
one "$AFTER" after-1 KINETIX_COMPILE_CACHE
one "$BEFORE" before-2 JAX_COMPILATION_CACHE_DIR
one "$AFTER" after-2 KINETIX_COMPILE_CACHE
