#!/usr/bin/env bash
# The issue-25 ablation: today's general-s recipe (pi-mlp 64, DR on fresh s levels, 256 envs, dense reward 0.1),
# each change alone, and all of them together, at equal wall-clock (the step budgets below come from throughput
# measured alone), every seed evaluated zero-shot with ATTEMPTS (50) episodes per level; curricula_summary.py
# prints the table.
#
#   benchmarks/ablation.sh OUT_DIR
#   VARIANTS="name:steps:setting,setting;..." (defaults below), SEEDS="0 1 2", ATTEMPTS=50,
#   SUITES="levels/s .cache/reference-levels/s"
#
# Step budgets: pi-mlp gets 2,000,000 env steps; rel-mlp 1,091,577 (`kinetix bench train --size s --models
# pi-mlp,rel-mlp --envs 256 --steps 32 --layers 3 --width 64`, 2026-11-26: 15,506 vs 8,463 env steps/s). SFL's
# scoring rollouts count in the budget (curricula_summary.py --training-steps). Masking and the reward scale cost
# nothing. The filtered, refreshed pool is not in the default list: at this scale its generation costs more time
# than the training it feeds (~49 s per 1,024 kept levels, against ~17 s for the 32 updates that use them), so it
# cannot be compared at equal wall-clock; its one run at equal steps was
#   VARIANTS="filter:2000000:levels.source=generated,levels.pool_size=1024,levels.refresh_every=32" SEEDS=0
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: $0 OUT_DIR" >&2
  exit 2
fi
out=$1
kinetix=${KINETIX:-.venv/bin/kinetix}
python=${PYTHON:-.venv/bin/python}
sfl=curriculum.name=sfl,curriculum.score_levels=384,curriculum.score_batch=128,curriculum.score_steps=256
sfl=$sfl,curriculum.score_attempts=2,curriculum.buffer_size=32,curriculum.refresh_every=64
rel=model.name=rel-mlp
default_variants="today:2000000:;rel:1091577:$rel;mask:2000000:model.mask_unused_actions=true"
default_variants="$default_variants;dense:2000000:env.dense_reward_scale=0.2;sfl:2000000:$sfl"
default_variants="$default_variants;all:1091577:$rel,model.mask_unused_actions=true,env.dense_reward_scale=0.2,$sfl"
suites=${SUITES:-levels/s .cache/reference-levels/s}
mkdir -p "$out"
IFS=';' read -ra variants <<<"${VARIANTS:-$default_variants}"
for variant in "${variants[@]}"; do
  IFS=: read -r name budget settings <<<"$variant"
  sets=()
  IFS=, read -ra pairs <<<"$settings"
  for pair in "${pairs[@]}"; do sets+=(--set "$pair"); done
  common=(--config experiments/cpu-small.yaml --set env.size=s --set levels.source=fresh --set model.width=64
    --set ppo.num_envs=256 --set ppo.num_steps=32 --set run.eval_every=0 "${sets[@]}")
  steps=$("$python" "$(dirname "$0")/curricula_summary.py" --training-steps "$budget" "${common[@]}")
  for seed in ${SEEDS:-0 1 2}; do
    dir=$out/$name-$seed
    [ -f "$dir/eval.json" ] && continue # done in an earlier call
    rm -rf "$dir"                         # an unfinished run starts over (its wall-clock time is part of the result)
    start=$(date +%s)
    "$kinetix" pretrain --run-dir "$dir" "${common[@]}" --set "ppo.total_timesteps=$steps" --set "run.seed=$seed"
    echo "$(($(date +%s) - start))" >"$dir/wall_seconds"
    # shellcheck disable=SC2086 # suites are space-separated folders
    ATTEMPTS=${ATTEMPTS:-50} "$(dirname "$0")/zero_shot.sh" "$dir" $suites
  done
done
"$python" "$(dirname "$0")/curricula_summary.py" "$out"
