#!/usr/bin/env bash
# The runs of PLAN.md: per training seed (SEEDS, default "20"; rule 4 decides whether "21 22" follow) four segments of
# 60 minutes of training time, each copied and evaluated on the validation suite. Run from the repository root, alone
# on the machine (the wall times are the record). Resumable: a copied segment is not redone; a segment cut off by the
# end of a session resumes from the run's last checkpoint to the same budget.
set -euo pipefail
out=docs/experiments/2026-11-30-agents-v4-round7
runs=runs/agents-v4-round7
kinetix=.venv/bin/kinetix
for seed in ${SEEDS:-20}; do
  run=$runs/K-$seed
  for minutes in 60 120 180 240; do
    copy=$runs/K-$seed@$minutes
    if [ ! -d "$copy" ]; then
      resume=()
      if [ -d "$run/checkpoints" ] && [ -n "$(ls -A "$run/checkpoints")" ]; then
        resume=(--resume)
      else
        rm -rf "$run"  # cut off before its first checkpoint: nothing to resume, start again
      fi
      /usr/bin/time -a -f "$minutes: %e s wall" -o "$out/K-$seed.time" $kinetix pretrain \
        --config experiments/general.yaml --run-dir "$run" "${resume[@]}" --set run.seed=$seed \
        --set run.minutes=$minutes --set ppo.total_timesteps=200_000_000 --set run.eval_every=0 \
        >>"$out/K-$seed.log" 2>&1
      cp -r "$run" "$copy.partial" && mv "$copy.partial" "$copy"
    fi
    record=$out/zero-shot-K$minutes-$seed.json
    [ -f "$record" ] || $kinetix validation run "$copy" --finetune-seeds '' --json "$record" \
      >"$out/zero-shot-K$minutes-$seed.log" 2>&1
    echo "K seed $seed at $minutes minutes done"
  done
  gzip -nc "$run/metrics.jsonl" >"$out/K-$seed.metrics.jsonl.gz"
done
