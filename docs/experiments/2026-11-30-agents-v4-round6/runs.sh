#!/usr/bin/env bash
# The runs of PLAN.md, each with its zero-shot validation, then the rule; run from the repository root, alone on the
# machine (the wall times are the record). Resumable: a run's `done` file or a written record is not redone.
set -euo pipefail
out=docs/experiments/2026-11-30-agents-v4-round6
runs=runs/agents-v4-round6
kinetix=.venv/bin/kinetix
for seed in 0 1 2; do
  run=$runs/I-$seed
  if [ ! -f "$run/done" ]; then
    rm -rf "$run"
    /usr/bin/time -f "%e s wall" -o "$out/I-$seed.time" $kinetix pretrain --config experiments/general.yaml \
      --run-dir "$run" --set env.size=l --set 'levels.fresh_like=[s,m,l]' --set run.init_from=general@3 \
      --set ppo.ent_coef=0.001 --set ppo.anneal_lr=true --set ppo.total_timesteps=4_915_200 --set run.minutes=30 \
      --set run.eval_every=0 --set run.seed=$seed >"$out/I-$seed.log" 2>&1
    gzip -nc "$run/metrics.jsonl" >"$out/I-$seed.metrics.jsonl.gz"
    touch "$run/done"
  fi
  [ -f "$out/zero-shot-I-$seed.json" ] || $kinetix validation run "$run" --finetune-seeds '' \
    --json "$out/zero-shot-I-$seed.json" >"$out/zero-shot-I-$seed.log" 2>&1
  echo "I seed $seed done"
done
python docs/experiments/2026-11-28-agents-v4/decide.py "$out" I \
  general-m=v3:docs/experiments/2026-11-29-agents-v4-round2/zero-shot-D-2.json >"$out/decide.txt"
