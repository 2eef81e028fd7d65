#!/usr/bin/env bash
# The solved set and the candidates of PLAN.md, each with its zero-shot validation; run from the repository root,
# alone on the machine (the wall times are the record). Resumable: a finished step (its .time file, a run's `done`
# file or a written record) is not redone.
set -euo pipefail
out=docs/experiments/2026-11-29-agents-v4-round2
runs=runs/agents-v4-round2
kinetix=.venv/bin/kinetix

if [ ! -f "$out/solve-m.time" ]; then
  rm -rf "$runs/gen-m" "$runs/solved-m"
  /usr/bin/time -f "%e s wall" -o "$out/generate-m.time" $kinetix generate --size m --count 256 --seed 204 \
    --out "$runs/gen-m" >"$out/generate-m.log" 2>&1
  /usr/bin/time -f "%e s wall" -o "$out/solve-m.time.part" $kinetix levels solve "$runs/gen-m" -o "$runs/solved-m" \
    --population 64 --iterations 10 --batch 64 --seed 0 >"$out/solve-m.log" 2>&1
  mv "$out/solve-m.time.part" "$out/solve-m.time"
  $kinetix levels info "$runs/solved-m" >"$out/info-m.txt" 2>&1
fi

for recipe in ${RECIPES:-C D}; do
  case $recipe in
    C) clone=(--set clone.levels=$runs/solved-m --set clone.coef=1.0 --set clone.batch=32) ;;
    D) clone=() ;;
  esac
  for seed in 0 1 2; do
    run=$runs/$recipe-$seed
    if [ ! -f "$run/done" ]; then
      rm -rf "$run"
      /usr/bin/time -f "%e s wall" -o "$out/$recipe-$seed.time" $kinetix pretrain --config experiments/general.yaml \
        --run-dir "$run" --set env.size=m --set run.init_from=general@3 "${clone[@]}" --set run.minutes=12 \
        --set ppo.total_timesteps=100_000_000 --set run.eval_every=0 --set run.seed=$seed >"$out/$recipe-$seed.log" 2>&1
      gzip -nc "$run/metrics.jsonl" >"$out/$recipe-$seed.metrics.jsonl.gz"
      touch "$run/done"
    fi
    [ -f "$out/zero-shot-$recipe-$seed.json" ] || $kinetix validation run "$run" --finetune-seeds '' \
      --json "$out/zero-shot-$recipe-$seed.json" >"$out/zero-shot-$recipe-$seed.log" 2>&1
    echo "$recipe seed $seed done"
  done
done
