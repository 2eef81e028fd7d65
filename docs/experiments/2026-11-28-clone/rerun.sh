#!/usr/bin/env bash
# RERUN.md's check: runs.sh, unchanged, with training seed 3 (arms P, L, C) in a fresh clone of main with its own .venv,
# alone on the machine; then its records copied here with the prefix rerun-. Run from the repository root:
# CLONE=<fresh clone, .venv built (make .venv/.installed-dev)> bash docs/experiments/2026-11-28-clone/rerun.sh. Resumable (runs.sh
# keeps a finished step); ARMS="P L" stops before C.
set -euo pipefail
out=$PWD/docs/experiments/2026-11-28-clone
cd "${CLONE:?a fresh clone of main, its .venv built (make .venv/.installed-dev)}"
echo "rerun at $(git rev-parse --short HEAD)"
SEEDS=3 ARMS="${ARMS:-P L C}" bash docs/experiments/2026-11-28-clone/runs.sh
here=docs/experiments/2026-11-28-clone
for name in generate solve; do
  cp "$here/$name.time" "$out/rerun-$name.time"
  cp "$here/$name.log" "$out/rerun-$name.log"
done
cp "$here/solved-info.txt" "$out/rerun-solved-info.txt"
sha256sum runs/clone/gen-s/shard-00000.npz runs/clone/solved-s/shard-00000.npz >"$out/rerun-sha256.txt"
for arm in P L C; do
  [ -f "$here/$arm-3.json" ] || continue
  for ext in json log time; do
    cp "$here/$arm-3.$ext" "$out/rerun-$arm-3.$ext"
  done
  [ ! -f "runs/clone/$arm-3/clone.jsonl" ] || cp "runs/clone/$arm-3/clone.jsonl" "$out/rerun-$arm-3.clone.jsonl"
  gzip -c "runs/clone/$arm-3/metrics.jsonl" >"$out/rerun-$arm-3.metrics.jsonl.gz"
done
