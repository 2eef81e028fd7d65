#!/usr/bin/env bash
# general v2 candidates (2026-11-27, second session): `general` v1 (general-s v2 + 400 updates at m) trained on for
# 256 updates (2,097,152 env steps, ~11 min) at size l with the v2 recipe, then blended half and half with general v1.
# The l suite is 40 of the 74 paper levels, so a point there is worth 0.54 points overall (s 0.14, m 0.32).
# Selection among general v1, the runs and the blends is on 120 held-out generated levels (40 per size, generate
# --seed 777, 20 attempts), not on the paper levels; the paper levels are evaluated for every candidate and reported.
# Usage: general-v3l.sh SEED
set -euo pipefail
cd "$(dirname "$0")/../.."
seed=$1
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
$k pretrain --config experiments/general.yaml --run-dir runs/general-v3l-seed$seed \
  --set env.size=l --set ppo.total_timesteps=2097152 --set run.init_from=general@1 \
  --set run.eval_every=0 --set run.seed=$seed --resume
$k agents blend general@1 runs/general-v3l-seed$seed -o runs/general-v3l-blend$seed --name general --version 2 \
  --command "kinetix agents blend general@1 runs/general-v3l-seed$seed -o runs/general-v3l-blend$seed --name general --version 2"
for p in runs/general-v3l-seed$seed runs/general-v3l-blend$seed; do
  $k eval $p "${held[@]}" --attempts 20 --seed 2000 --json $p-heldout.json
  $k eval $p "${paper[@]}" --attempts 50 --seed 1000 --json $p-paper-1000.json
done
