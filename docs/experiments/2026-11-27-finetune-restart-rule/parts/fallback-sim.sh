#!/usr/bin/env bash
# issue 25: what a two-phase fine-tuning rule would score, simulated from separate runs (the rule is not built):
# fine-tune general-s v2 as usual; if no episode was solved in the first 51,200 steps (a quarter of the 200K
# budget), restart with only its features loaded (fresh policy head and critic) for the remaining ~150K steps.
# From the plain fine-tuned runs' metrics, the rule restarts rocket-car-jump seeds 0-2, jet-ball-hop 0 and 2 and
# aim-then-fire 0 and 2 (none of the others): those get a features-only run of 147,456 steps (72 updates) here.
set -euo pipefail
out=${OUT:-runs/ft-v2-fallback}
for pair in rocket-car-jump:levels/s:0 rocket-car-jump:levels/s:1 rocket-car-jump:levels/s:2 \
  jet-ball-hop:levels/s:0 jet-ball-hop:levels/s:2 aim-then-fire:levels/s:0 aim-then-fire:levels/s:2; do
  IFS=: read -r name folder seed <<<"$pair"
  level=$folder/$name.json
  dir=$out/$name/fallback-$seed
  [ -f "$dir/eval.json" ] && continue
  rm -rf "$dir"
  .venv/bin/kinetix finetune "$level" --from general-s --run-dir "$dir" --config experiments/cpu-small.yaml \
    --set ppo.total_timesteps=147456 --set run.seed=$seed --set run.eval_every=25 \
    --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01 --set run.fresh_policy_head=true --set run.fresh_critic=true
  .venv/bin/kinetix eval "$dir" --levels "$level" --attempts 50 --seed 1000 --json "$dir/eval.json"
done
