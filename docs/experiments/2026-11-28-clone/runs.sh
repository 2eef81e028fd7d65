#!/usr/bin/env bash
# PLAN.md's solved set and arms; run from the repository root, one job at a time. Resumable: a finished step is kept.
set -euo pipefail
out=docs/experiments/2026-11-28-clone
kinetix=.venv/bin/kinetix
if [ ! -f runs/clone/solved-s/manifest.json ]; then
  rm -rf runs/clone/gen-s runs/clone/solved-s
  /usr/bin/time -f "%e s wall" -o "$out/generate.time" $kinetix generate --size s --count 256 --seed 101 \
    --out runs/clone/gen-s >"$out/generate.log" 2>&1
  /usr/bin/time -f "%e s wall" -o "$out/solve.time" $kinetix levels solve runs/clone/gen-s -o runs/clone/solved-s \
    --population 64 --iterations 10 --batch 64 --seed 0 >"$out/solve.log" 2>&1
  $kinetix levels info runs/clone/solved-s >"$out/solved-info.txt" 2>&1
fi
solver=$(python3 -c "print(sum(float(open(f'$out/{n}.time').read().split()[0]) for n in ('generate', 'solve')) / 60)")
budget=$(python3 -c "print(round(30 - $solver, 2))")
echo "solver ${solver} min; cloning runs get ${budget} min"
# Seed by seed (P, C, L for seed 0, then seed 1, ...), so that a session that stops part way has compared arms.
for seed in ${SEEDS:-0 1 2}; do
  for arm in ${ARMS:-P C L}; do
    case $arm in
      P) extra=(--set run.minutes=30) ;;
      C) extra=(--set clone.levels=runs/clone/solved-s --set clone.updates=200 --set clone.batch=32 --set run.minutes=$budget) ;;
      L) extra=(--set clone.levels=runs/clone/solved-s --set clone.coef=1.0 --set clone.batch=32 --set run.minutes=$budget) ;;
    esac
    [ ! -f runs/clone/STOP ] || { echo "runs/clone/STOP found: stopping before $arm seed $seed"; exit 0; }
    run=runs/clone/$arm-$seed
    if [ ! -f "$run/done" ]; then
      rm -rf "$run"
      /usr/bin/time -f "%e s wall" -o "$out/$arm-$seed.time" $kinetix pretrain --config experiments/general.yaml \
        --run-dir "$run" --set run.seed=$seed "${extra[@]}" --set ppo.total_timesteps=100_000_000 \
        --set run.eval_every=0 >"$out/$arm-$seed.log" 2>&1
      touch "$run/done"
    fi
    [ -f "$out/$arm-$seed.json" ] || $kinetix eval "$run" --levels validation --attempts 50 --seed 1000 \
      --json "$out/$arm-$seed.json" >/dev/null
    echo "$arm seed $seed done"
  done
done
