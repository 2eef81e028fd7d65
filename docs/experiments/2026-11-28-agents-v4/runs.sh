#!/usr/bin/env bash
# The candidates of PLAN.md and their zero-shot validation; run from the repository root. Resumable: a finished run
# (its `done` file) or a written record is not redone.
set -euo pipefail
out=docs/experiments/2026-11-28-agents-v4
kinetix=.venv/bin/kinetix
for recipe in ${RECIPES:-A B}; do
  case $recipe in
    A) parent=general-s@2 size=s ;;
    B) parent=general@3 size=m ;;
  esac
  for seed in 0 1 2; do
    run=runs/agents-v4/$recipe-$seed
    if [ ! -f "$run/done" ]; then
      rm -rf "$run"
      /usr/bin/time -f "%e s wall" -o "$out/$recipe-$seed.time" $kinetix pretrain --config experiments/general.yaml \
        --run-dir "$run" --set env.size=$size --set run.init_from=$parent --set model.mirror=geometric \
        --set ppo.total_timesteps=2097152 --set run.eval_every=0 --set run.seed=$seed >"$out/$recipe-$seed.log" 2>&1
      touch "$run/done"
    fi
    [ -f "$out/zero-shot-$recipe-$seed.json" ] || $kinetix validation run "$run" --finetune-seeds '' \
      --json "$out/zero-shot-$recipe-$seed.json" >"$out/zero-shot-$recipe-$seed.log" 2>&1
    echo "$recipe seed $seed done"
  done
done
