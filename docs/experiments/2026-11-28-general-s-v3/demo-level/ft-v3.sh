#!/usr/bin/env bash
# general-s v3 fine-tuned on make demo's level with make demo's settings, seeds 0 1 2 (2026-11-28 ~12:00 UTC).
# As run, the source was `--from general-s` while v3 was the newest general-s; general-s@3 names the same agent.
set -euo pipefail
k=.venv/bin/kinetix
level=levels/m/two-link-reach.json
$k eval general-s@3 --levels $level --json general-s-v3-zero-shot.json
for s in 0 1 2; do
  $k finetune $level --from general-s@3 --run-dir runs/gs3-demo-ft$s --config experiments/cpu-small.yaml \
    --set ppo.total_timesteps=200000 --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01 --set run.seed=$s
  $k eval runs/gs3-demo-ft$s --levels $level --json finetune-v3-seed$s-eval.json
done
