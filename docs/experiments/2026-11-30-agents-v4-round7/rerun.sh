#!/usr/bin/env bash
# RERUN.md's check: K with training seed 23 in a fresh clone of main ($CLONE), alone and resumable (runs.sh), then the
# rule over seeds 20-23. The records land beside this file in the checkout it is run from:
#   CLONE=<fresh clone of main> bash docs/experiments/2026-11-30-agents-v4-round7/rerun.sh
set -euo pipefail
rel=docs/experiments/2026-11-30-agents-v4-round7
out=$PWD/$rel
here=$PWD
[ -f "$out/decide.txt" ] || { echo "$rel/decide.txt: missing; the re-run tests the decision" >&2; exit 2; }
cd "$CLONE"
make .venv/.installed-dev >/dev/null
SEEDS=23 bash "$rel/runs.sh"
for f in K-23.log K-23.time K-23.metrics.jsonl.gz zero-shot-K{60,120,180,240}-23.{json,log}; do
  cp "$rel/$f" "$out/$f"
done
git rev-parse HEAD >"$out/rerun-commit.txt"
cd "$here"
python docs/experiments/2026-11-28-agents-v4/decide.py "$rel" K60 K120 K180 K240 seeds=20,21,22,23 \
  general-m=v3:docs/experiments/2026-11-29-agents-v4-round2/zero-shot-D-2.json >"$out/rerun-decide.txt"
