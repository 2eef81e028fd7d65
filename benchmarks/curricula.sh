#!/usr/bin/env bash
# DR vs SFL vs PLR vs ACCEL at equal environment steps (scoring rollouts counted), on fresh levels of one size, SEEDS each;
# every final policy is evaluated zero-shot with ATTEMPTS sampled episodes per level on the hand-made suites.
# curricula_summary.py prints the table (mean, spread and every seed) next to random play.
#
#   benchmarks/curricula.sh BUDGET OUT_DIR
#   SIZE=s CURRICULA="dr sfl plr accel" SEEDS="0 1 2" CONFIG=experiments/cpu-small.yaml ATTEMPTS=20 ENVS=256 (defaults)
#   SUITES="levels/$SIZE .cache/reference-levels/$SIZE" (make reference-levels fetches the paper's levels)
#   EVAL_EVERY=0 EVAL_LEVELS=levels/$SIZE: evaluate during training every EVAL_EVERY updates (learning curves)
#
# Equal budgets: DR and PLR runs take BUDGET update steps (PLR's updates on new levels, which train nothing, are
# part of them); an SFL run takes fewer updates, so that its updates plus its scoring rollouts make BUDGET. Every
# run's metrics.jsonl records total_steps (all environment steps), which the summary checks. DR and SFL play ENVS
# environments x 32 steps per update; PLR and ACCEL reset all environments each update, so they play ENVS/8 x 256 steps
# (the same batch; a rollout must hold whole episodes of env.max_steps 256), with a buffer of PLR_BUFFER=512 levels.
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: $0 BUDGET OUT_DIR" >&2
  exit 2
fi
budget=$1 out=$2
kinetix=${KINETIX:-.venv/bin/kinetix}
python=${PYTHON:-.venv/bin/python}
config=${CONFIG:-experiments/cpu-small.yaml}
size=${SIZE:-s}
envs=${ENVS:-256}
suites=${SUITES:-levels/$size .cache/reference-levels/$size}
sets=()
for s in ${SETS:-}; do sets+=(--set "$s"); done
mkdir -p "$out"
for curriculum in ${CURRICULA:-dr sfl plr accel}; do
  for seed in ${SEEDS:-0 1 2}; do
    dir=$out/$curriculum-$seed
    [ -f "$dir/eval.json" ] && continue # done in an earlier call
    shape=(--set "ppo.num_envs=$envs" --set ppo.num_steps=32)
    [[ "$curriculum" = plr || "$curriculum" = accel ]] && shape=(--set "ppo.num_envs=$((envs / 8))" --set ppo.num_steps=256
      --set "curriculum.buffer_size=${PLR_BUFFER:-512}")
    common=(--config "$config" --set env.size="$size" --set levels.source=fresh --set "curriculum.name=$curriculum"
      --set "run.seed=$seed" --set "run.eval_every=${EVAL_EVERY:-0}" --set "run.eval_levels=[${EVAL_LEVELS:-levels/$size}]"
      "${shape[@]}" "${sets[@]}")
    steps=$("$python" "$(dirname "$0")/curricula_summary.py" --training-steps "$budget" "${common[@]}")
    if [ -d "$dir" ]; then
      "$kinetix" pretrain --run-dir "$dir" --resume "${common[@]}" --set "ppo.total_timesteps=$steps"
    else
      "$kinetix" pretrain --run-dir "$dir" "${common[@]}" --set "ppo.total_timesteps=$steps"
    fi
    # shellcheck disable=SC2086 # suites are space-separated folders
    "$(dirname "$0")/zero_shot.sh" "$dir" $suites
  done
done
"$python" "$(dirname "$0")/curricula_summary.py" "$out"
