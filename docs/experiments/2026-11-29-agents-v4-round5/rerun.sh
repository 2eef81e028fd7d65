#!/usr/bin/env bash
# RERUN.md's check: H with training seed 3 in a fresh clone of main ($CLONE), alone, then its zero-shot validation;
# the records land beside this file in the checkout it is run from, then the fourth round's held.py decides.
set -euo pipefail
out=$PWD/docs/experiments/2026-11-29-agents-v4-round5
here=$PWD
cd "$CLONE"
make .venv/.installed-dev >/dev/null
kinetix=.venv/bin/kinetix
run=runs/agents-v4-round5/H-3
rm -rf "$run"
/usr/bin/time -f "%e s wall" -o "$out/rerun-H-3.time" $kinetix pretrain --config experiments/general.yaml \
  --run-dir "$run" --set env.size=l --set 'levels.fresh_like=[s,m,l]' \
  --set run.init_from=general-s@2 --set run.minutes=28 --set ppo.total_timesteps=100_000_000 --set run.eval_every=0 \
  --set run.seed=3 >"$out/rerun-H-3.log" 2>&1
gzip -nc "$run/metrics.jsonl" >"$out/rerun-H-3.metrics.jsonl.gz"
$kinetix validation run "$run" --finetune-seeds '' --json "$out/rerun-zero-shot-H-3.json" \
  >"$out/rerun-zero-shot-H-3.log" 2>&1
git rev-parse HEAD >"$out/rerun-commit.txt"
cd "$here"
python docs/experiments/2026-11-29-agents-v4-round4/held.py \
  H=docs/experiments/2026-11-29-agents-v4-round5 >"$out/rerun-held.txt"
