#!/usr/bin/env bash
# Step 4 of PLAN.md for the one shipped candidate, D-2 (decide.txt, validation-D-2.json): the test suite at evaluation
# seeds 1000 and 1001, the card's evaluation (the paper's m levels and ours, as general-m v2's card has), then the
# agent folder with its card and record. Run from the checkout's root after test.sh and `make reference-levels`.
set -euo pipefail
out=docs/experiments/2026-11-29-agents-v4-round2
run=runs/agents-v4-round2/D-2
kinetix=.venv/bin/kinetix
shipped=src/kinetix_cli/rl/shipped
[ -f "$out/test-D-2-1001.json" ] || $kinetix eval "$run" --levels test --attempts 50 --seed 1001 \
  --json "$out/test-D-2-1001.json" >"$out/test-D-2-1001.log" 2>&1
[ -f "$out/card-eval-D-2.json" ] || $kinetix eval "$run" --levels .cache/reference-levels/m --levels levels/m \
  --attempts 50 --seed 1000 --json "$out/card-eval-D-2.json" >"$out/card-eval-D-2.log" 2>&1
# the chosen version takes the name; v2 stays loadable as general-m@2
[ -d "$shipped/general-m@2" ] || git mv "$shipped/general-m" "$shipped/general-m@2"
$kinetix agents export "$run" -o "$shipped/general-m" --name general-m --version 3 --eval "$out/card-eval-D-2.json" \
  --command "# general v3 first (kinetix_cli/rl/shipped/general/agent.json lists its parts and commands: about 114 minutes of training)" \
  --command "kinetix pretrain --config experiments/general.yaml --run-dir runs/agents-v4-round2/D-2 --set env.size=m --set run.init_from=general@3 --set run.minutes=12 --set ppo.total_timesteps=100_000_000 --set run.eval_every=0 --set run.seed=2" \
  --command "# general v3 trained on for 12 minutes at size m (2026-11-29 19:51-20:03 UTC, alone on the 2-core VM): the final checkpoint, update 647, 5,300,224 env steps; recipe D of docs/experiments/2026-11-29-agents-v4-round2/PLAN.md, seed 2 chosen by its rule 2 on the validation suite's m levels" \
  --command "kinetix eval runs/agents-v4-round2/D-2 --levels .cache/reference-levels/m --levels levels/m --attempts 50 --seed 1000 --json card-eval-D-2.json  # read after the choice"
$kinetix agents record "$shipped/general-m" --validation "$out/validation-D-2.json" --test "$out/test-D-2-1000.json" \
  --test "$out/test-D-2-1001.json" --rule "docs/experiments/2026-11-29-agents-v4-round2/PLAN.md, rule 2: the recipe with the higher seed mean over the validation suite's m levels (held-out m and levels/m) ships if it beats the shipped general-m v2 (8.37%) by more than max(1.0 point, its seed sd): D (general v3 + 12 min at m, seeds 0-2) 10.40% (sd 1.51), C 7.17%; its best seed at m, D-2 (11.7%); rule 3: fine-tuned 100% (two levels x 3 seeds)"
