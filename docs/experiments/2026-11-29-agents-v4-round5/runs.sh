#!/usr/bin/env bash
# The runs of PLAN.md, each with its zero-shot validation, then the rule; run from the repository root, alone on the
# machine (the wall times are the record). Resumable: a run's `done` file or a written record is not redone.
set -euo pipefail
out=docs/experiments/2026-11-29-agents-v4-round5
runs=runs/agents-v4-round5
kinetix=.venv/bin/kinetix
for seed in 0 1 2; do
  run=$runs/H-$seed
  if [ ! -f "$run/done" ]; then
    rm -rf "$run"
    /usr/bin/time -f "%e s wall" -o "$out/H-$seed.time" $kinetix pretrain --config experiments/general.yaml \
      --run-dir "$run" --set env.size=l --set 'levels.fresh_like=[s,m,l]' \
      --set run.init_from=general-s@2 --set run.minutes=28 --set ppo.total_timesteps=100_000_000 --set run.eval_every=0 \
      --set run.seed=$seed >"$out/H-$seed.log" 2>&1
    gzip -nc "$run/metrics.jsonl" >"$out/H-$seed.metrics.jsonl.gz"
    touch "$run/done"
  fi
  [ -f "$out/zero-shot-H-$seed.json" ] || $kinetix validation run "$run" --finetune-seeds '' \
    --json "$out/zero-shot-H-$seed.json" >"$out/zero-shot-H-$seed.log" 2>&1
  echo "H seed $seed done"
done
python docs/experiments/2026-11-28-agents-v4/decide.py "$out" H \
  general-m=v3:docs/experiments/2026-11-29-agents-v4-round2/zero-shot-D-2.json >"$out/decide.txt"
