#!/usr/bin/env bash
# Solved level sets of every size (issue 48, lever 2's data): 1,024 generated levels of s, m and l each, searched by
# the batched solver, written to runs/solved-sets/{s,m,l}. Run from the repository root, alone on the machine (the
# times are the record). Resumable: generate and solve both resume a killed folder at its last written shard; a
# finished step is kept. l's solve takes longer than a session (about 9 s a level), so its sets are written in shards
# of 64 levels (the solve inherits its source's shards; `levels solve --shard-size`, added after this set was
# generated, now gives the same without regenerating, but a set's shard size is part of its identity, so the
# study keeps the layout it ran with); a step stopped part way (its kinetix process killed, not this script's `time`) keeps its wall time
# as NAME.time.stopped-N, and its log grows across the parts.
set -euo pipefail
out=docs/experiments/2026-11-29-solved-sets
kinetix=.venv/bin/kinetix

timed() {  # timed NAME COMMAND...: run once, its wall time to $out/NAME.time (only when it succeeded), its log beside
  local name=$1
  shift
  [ ! -f "$out/$name.time" ] || return 0
  if /usr/bin/time -f "%e s wall" -o "$out/$name.time.part" "$@" >>"$out/$name.log" 2>&1; then
    mv "$out/$name.time.part" "$out/$name.time"
  else
    local n=1
    while [ -f "$out/$name.time.stopped-$n" ]; do n=$((n + 1)); done
    mv "$out/$name.time.part" "$out/$name.time.stopped-$n"
    echo "$name stopped part way; its time so far in $out/$name.time.stopped-$n" >&2
    return 1
  fi
}

for size in ${SIZES:-s m l}; do
  case $size in s) seed=201 shards=() ;; m) seed=202 shards=() ;; l) seed=203 shards=(--shard-size 64) ;; esac
  timed "generate-$size" $kinetix generate --size "$size" --count 1024 --seed $seed --out "runs/solved-sets/gen-$size" \
    "${shards[@]}"
  timed "solve-$size" $kinetix levels solve "runs/solved-sets/gen-$size" -o "runs/solved-sets/$size" \
    --population 64 --iterations 10 --batch 64 --seed 0
  $kinetix levels info "runs/solved-sets/$size" >"$out/info-$size.txt" 2>&1
  echo "$size: $(sed -n 2p "$out/info-$size.txt")"
done
