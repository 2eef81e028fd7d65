#!/usr/bin/env bash
# Carries rerun.sh across sessions whose checkout starts new (the run directory is outside git, so it does not carry
# over). Run from the repository root of the checkout that holds the records:
#   bash docs/experiments/2026-11-30-agents-v4-round7/carry.sh save CLONE      # rerun.sh stopped: then commit
#   bash docs/experiments/2026-11-30-agents-v4-round7/carry.sh restore CLONE   # in a fresh clone, before rerun.sh
# save keeps the run's newest checkpoint, its metrics and config, and the seed-23 records so far (K-23.log and .time,
# each finished copy's zero-shot record); a copy whose record exists comes back as a marker (its config alone), so
# runs.sh neither trains nor evaluates it again. The tarball goes once the re-run's records are in.
set -euo pipefail
shopt -s nullglob
rel=docs/experiments/2026-11-30-agents-v4-round7
out=$PWD/$rel
tarball=$out/rerun-carry.tar.gz
runs=runs/agents-v4-round7
[ $# -eq 2 ] && [ -d "$2" ] || { echo "usage: carry.sh save|restore CLONE (an existing directory)" >&2; exit 2; }
cd "$2"
case "$1" in
save)
  for pid in $(pgrep -f -- "--run-dir $runs/K-23" || true); do  # a trainer in this clone
    [ "$(readlink "/proc/$pid/cwd")" != "$(pwd -P)" ] || { echo "$runs/K-23: still training; stop rerun.sh first" >&2; exit 2; }
  done
  run=$runs/K-23
  newest=$(ls "$run/checkpoints" | sort -n | tail -1)
  [ -n "$newest" ] || { echo "$run/checkpoints: empty; nothing to carry" >&2; exit 2; }
  keep=("$run/config.yaml" "$run/versions.json" "$run/metrics.jsonl" "$run/checkpoints/$newest")
  for copy in "$run"@*; do
    if [ -f "$rel/zero-shot-K${copy##*@}-23.json" ]; then keep+=("$copy/config.yaml"); else keep+=("$copy"); fi
  done
  tar -czf "$tarball" "${keep[@]}"
  for f in "$rel"/K-23.log "$rel"/K-23.time "$rel"/zero-shot-K*-23.json "$rel"/zero-shot-K*-23.log; do
    [ ! -f "$f" ] || cp "$f" "$out/"
  done
  echo "carried: $newest updates; $(du -h "$tarball" | cut -f1) in $rel/rerun-carry.tar.gz"
  ;;
restore)
  [ -f "$tarball" ] || { echo "$rel/rerun-carry.tar.gz: missing" >&2; exit 2; }
  [ ! -e "$runs/K-23" ] || { echo "$2/$runs/K-23: exists; restore into a fresh clone" >&2; exit 2; }
  tar -xzf "$tarball"
  echo "restored: $runs/K-23 at $(ls "$runs/K-23/checkpoints") updates"
  ;;
*) echo "carry.sh: $1: not save or restore" >&2; exit 2 ;;
esac
