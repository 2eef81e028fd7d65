#!/usr/bin/env bash
# RERUN.md's check: D, E, F and G with training seed 3 in a fresh clone of main ($CLONE), alone, then the zero-shot
# validation of E-3, F-3 and G-3; the records land beside this file (and the third round's) in the checkout it is
# run from, then held.py decides.
set -euo pipefail
out=$PWD/docs/experiments/2026-11-29-agents-v4-round4
out3=$PWD/docs/experiments/2026-11-29-agents-v4-round3
here=$PWD
cd "$CLONE"
make .venv/.installed-dev >/dev/null
kinetix=.venv/bin/kinetix
common=(--config experiments/general.yaml --set run.init_from=general@3 --set run.minutes=12
  --set ppo.total_timesteps=100_000_000 --set run.eval_every=0 --set run.seed=3)
rm -rf runs/agents-v4-round2/D-3 runs/agents-v4-round4/G-3 runs/agents-v4-round3/E-3 runs/agents-v4-round3/F-3
/usr/bin/time -f "%e s wall" -o "$out3/rerun-D-3.time" $kinetix pretrain "${common[@]}" --set env.size=m \
  --run-dir runs/agents-v4-round2/D-3 >"$out3/rerun-D-3.log" 2>&1
/usr/bin/time -f "%e s wall" -o "$out/rerun-G-3.time" $kinetix pretrain "${common[@]}" --set env.size=s \
  --run-dir runs/agents-v4-round4/G-3 >"$out/rerun-G-3.log" 2>&1
gzip -nc runs/agents-v4-round4/G-3/metrics.jsonl >"$out/rerun-G-3.metrics.jsonl.gz"
$kinetix agents blend runs/agents-v4-round2/D-3 general-s@2 -o runs/agents-v4-round3/E-3 --name general --version 4 \
  >"$out3/rerun-blend-E-3.log" 2>&1
$kinetix agents blend runs/agents-v4-round2/D-3 general@3 -o runs/agents-v4-round3/F-3 --name general --version 4 \
  >"$out3/rerun-blend-F-3.log" 2>&1
for run in round3/E-3 round3/F-3 round4/G-3; do
  dest=$out3 && [ "${run%%/*}" = round4 ] && dest=$out
  $kinetix validation run "runs/agents-v4-$run" --finetune-seeds '' --json "$dest/rerun-zero-shot-${run#*/}.json" \
    >"$dest/rerun-zero-shot-${run#*/}.log" 2>&1
done
git rev-parse HEAD >"$out/rerun-commit.txt"
cd "$here"
python docs/experiments/2026-11-29-agents-v4-round4/held.py >"$out/rerun-held.txt"
