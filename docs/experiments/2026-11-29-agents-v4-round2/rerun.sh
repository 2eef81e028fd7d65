#!/usr/bin/env bash
# RERUN.md's check: recipe D with training seed 3 in a fresh clone of main ($CLONE), alone, then its zero-shot
# validation; the records land beside this file in the checkout it is run from.
set -euo pipefail
out=$PWD/docs/experiments/2026-11-29-agents-v4-round2
cd "$CLONE"
make .venv/.installed-dev >/dev/null
kinetix=.venv/bin/kinetix
rm -rf runs/agents-v4-round2/D-3
/usr/bin/time -f "%e s wall" -o "$out/rerun-D-3.time" $kinetix pretrain --config experiments/general.yaml \
  --run-dir runs/agents-v4-round2/D-3 --set env.size=m --set run.init_from=general@3 --set run.minutes=12 \
  --set ppo.total_timesteps=100_000_000 --set run.eval_every=0 --set run.seed=3 >"$out/rerun-D-3.log" 2>&1
gzip -nc runs/agents-v4-round2/D-3/metrics.jsonl >"$out/rerun-D-3.metrics.jsonl.gz"
$kinetix validation run runs/agents-v4-round2/D-3 --finetune-seeds '' --json "$out/rerun-zero-shot-D-3.json" \
  >"$out/rerun-zero-shot-D-3.log" 2>&1
git rev-parse HEAD >"$out/rerun-commit.txt"
