#!/usr/bin/env bash
# RERUN.md's check: the plain and Y arms with training seed 3 from a fresh clone, 10 minutes each, one at a time and
# alone, then validation and its mirror image. Run from the repository root: CLONE=<fresh clone with its .venv>
# bash docs/experiments/2026-11-29-mirror-loss/rerun.sh. Resumable: a finished step is kept.
set -euo pipefail
out=$PWD/docs/experiments/2026-11-29-mirror-loss
cd "${CLONE:?a fresh clone of main, its .venv built (make .venv/.installed-dev)}"
kinetix=.venv/bin/kinetix
[ -d runs/validation-mirror ] || $kinetix levels mirror validation -o runs/validation-mirror
for arm in plain Y; do
  run=runs/rerun/$arm-3
  extra=()
  [ "$arm" = plain ] || extra=(--set ppo.mirror_coef=1.0 --set ppo.mirror_share=0.25)
  if [ ! -f "$run/done" ]; then
    rm -rf "$run"
    /usr/bin/time -f "%e s wall" -o "$out/rerun-$arm-3.time" $kinetix pretrain --config experiments/general.yaml \
      --run-dir "$run" --set run.seed=3 "${extra[@]}" --set run.minutes=10 --set ppo.total_timesteps=100_000_000 \
      --set run.eval_every=0 >"$out/rerun-$arm-3.log" 2>&1
    touch "$run/done"
  fi
  cp "$run/metrics.jsonl" "$out/rerun-$arm-3.metrics.jsonl"
  echo "$arm-3 trained at $(git rev-parse --short HEAD)"
done
for arm in plain Y; do
  run=runs/rerun/$arm-3
  [ -f "$out/rerun-$arm-3.json" ] || $kinetix eval "$run" --levels validation --attempts 50 --seed 1000 \
    --json "$out/rerun-$arm-3.json" >/dev/null
  [ -f "$out/rerun-$arm-3-mirrorimage.json" ] || $kinetix eval "$run" --levels runs/validation-mirror \
    --attempts 50 --seed 1000 --json "$out/rerun-$arm-3-mirrorimage.json" >/dev/null
  echo "$arm-3 evaluated"
done
