#!/usr/bin/env bash
# Rule 5 of PLAN.md for one candidate that decide.txt names and full.sh passed (fine-tuning mean at least 50%): the
# test suite at evaluation seed 1001 (1000 is test.sh's), the card's evaluation, then the agent folder with its card
# and record. The previous version stays loadable as NAME@OLD. Run from the checkout's root after test.sh:
#   bash docs/experiments/2026-11-30-agents-v4-round7/ship.sh NAME VERSION COPY "RULE"
# e.g. ship.sh general-l 3 K-21@240 "PLAN.md rule 2: ..." (RULE: decide.txt's line for NAME and rule 3's result).
set -euo pipefail
[ $# -eq 4 ] || { echo "usage: ship.sh NAME VERSION COPY RULE" >&2; exit 2; }
name=$1 version=$2 copy=$3 rule=$4
out=docs/experiments/2026-11-30-agents-v4-round7
run=runs/agents-v4-round7/$copy
kinetix=.venv/bin/kinetix
shipped=src/kinetix_cli/rl/shipped
seed=${copy#K-}; seed=${seed%@*}; minutes=${copy#*@}; tag=K$minutes-$seed
for f in "$out/decide.txt" "$out/validation-$copy.json" "$out/test-$tag-1000.json"; do
  [ -f "$f" ] || { echo "$f: missing (decide, full.sh and test.sh come first)" >&2; exit 2; }
done
[ -f "$out/test-$tag-1001.json" ] || $kinetix eval "$run" --levels test --attempts 50 --seed 1001 \
  --json "$out/test-$tag-1001.json" >"$out/test-$tag-1001.log" 2>&1
card=$out/card-eval-$tag.json
if [ "$name" = general ]; then
  card=$out/test-$tag-1000.json  # general's card holds the paper's three sizes, as v3's does
else
  size=${name#general-}
  [ -f "$card" ] || $kinetix eval "$run" --levels ".cache/reference-levels/$size" --levels "levels/$size" \
    --attempts 50 --seed 1000 --json "$card" >"$out/card-eval-$tag.log" 2>&1
fi
old=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['version'])" "$shipped/$name/agent.json")
[ -d "$shipped/$name@$old" ] || git mv "$shipped/$name" "$shipped/$name@$old"
$kinetix agents export "$run" -o "$shipped/$name" --name "$name" --version "$version" --eval "$card" \
  --command "kinetix pretrain --config experiments/general.yaml --run-dir runs/agents-v4-round7/K-$seed --set run.seed=$seed --set run.minutes=60 --set ppo.total_timesteps=200_000_000 --set run.eval_every=0" \
  --command "# then the same with --resume and run.minutes=120, 180, 240 in turn, up to $minutes (2026-11-30, alone on the 2-core VM; recipe K of docs/experiments/2026-11-30-agents-v4-round7/PLAN.md, its runs.sh): the checkpoint after $minutes minutes of training" \
  --command "kinetix eval runs/agents-v4-round7/K-$seed@$minutes --levels test --attempts 50 --seed 1000  # read after the choice"
$kinetix agents record "$shipped/$name" --validation "$out/validation-$copy.json" --test "$out/test-$tag-1000.json" \
  --test "$out/test-$tag-1001.json" --rule "$rule"
