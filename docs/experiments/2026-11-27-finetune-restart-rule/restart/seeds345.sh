#!/usr/bin/env bash
# issue 25: the restart rule checked on seeds it was not picked on (3, 4, 5), on the six fine-tuning levels:
# the rule's arm (ft-v2-restart.sh) and scratch (general-s v2's network from scratch, the tables' settings), both
# 200K steps, 50 attempts at evaluation seed 1000. Seeds 3 and 4 of rocket-car-jump and two-link-reach ran first
# (seeds34.sh, same settings); by default this runs the rest. FIRST_SEEDS, REST_SEEDS, OUT choose.
set -euo pipefail
out=${OUT:-runs/ft-v2-seeds345}
rest="levels/s/pad-to-pad.json .cache/reference-levels/s/h1_thrust_over_ball.json \
.cache/reference-levels/s/h3_point_the_thruster.json levels/s/jet-ball-hop.json"
first="levels/s/rocket-car-jump.json levels/m/two-link-reach.json"
run() {  # LEVELS SEEDS (none: nothing to run)
  [ -n "$2" ] || return 0
  OUT=$out SEEDS="$2" LEVELS="$1" benchmarks/finetune-v2-restart-cpu-2026-11-27/ft-v2-restart.sh
  for level in $1; do
    name=$(basename "$level" .json)
    for seed in $2; do
      dir=$out/$name/scratch-$seed
      [ -f "$dir/eval.json" ] && continue
      rm -rf "$dir"
      .venv/bin/kinetix finetune "$level" --from none --run-dir "$dir" --config experiments/cpu-small.yaml \
        --set ppo.total_timesteps=200000 --set run.seed=$seed --set run.eval_every=25 \
        --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01 \
        --set model.name=rel-mlp --set model.width=64 --set model.mask_unused_actions=true
      .venv/bin/kinetix eval "$dir" --levels "$level" --attempts 50 --seed 1000 --json "$dir/eval.json"
    done
  done
}
run "${FIRST:-$first}" "${FIRST_SEEDS-5}"
run "${REST:-$rest}" "${REST_SEEDS-3 4 5}"
