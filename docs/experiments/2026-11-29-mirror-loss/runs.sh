#!/usr/bin/env bash
# PLAN.md's Y arm (10 minutes each, seeds 0-2, one run at a time, nothing else running) and the mirror-image
# evaluations of both arms. Run from the repository root. Resumable: a finished step is kept.
set -euo pipefail
out=docs/experiments/2026-11-29-mirror-loss
kinetix=.venv/bin/kinetix
[ -d runs/validation-mirror ] || $kinetix levels mirror validation -o runs/validation-mirror
for seed in ${SEEDS:-0 1 2}; do
  run=runs/mirror-loss/Y-$seed
  if [ ! -f "$run/done" ]; then
    rm -rf "$run"
    /usr/bin/time -f "%e s wall" -o "$out/Y-$seed.time" $kinetix pretrain --config experiments/general.yaml \
      --run-dir "$run" --set run.seed=$seed --set ppo.mirror_coef=1.0 --set ppo.mirror_share=0.25 \
      --set run.minutes=10 --set ppo.total_timesteps=100_000_000 --set run.eval_every=0 >"$out/Y-$seed.log" 2>&1
    touch "$run/done"
  fi
  cp "$run/metrics.jsonl" "$out/Y-$seed.metrics.jsonl"
  [ -f "$out/Y-$seed.json" ] || $kinetix eval "$run" --levels validation --attempts 50 --seed 1000 \
    --json "$out/Y-$seed.json" >/dev/null
  [ -f "$out/Y-$seed-mirrorimage.json" ] || $kinetix eval "$run" --levels runs/validation-mirror --attempts 50 \
    --seed 1000 --json "$out/Y-$seed-mirrorimage.json" >/dev/null
  plain=runs/batch-scale/minutes-256-$seed
  [ -f "$out/plain-$seed-mirrorimage.json" ] || $kinetix eval "$plain" --levels runs/validation-mirror \
    --attempts 50 --seed 1000 --json "$out/plain-$seed-mirrorimage.json" >/dev/null
  echo "Y seed $seed done"
done
