"""The tiny training run most RL and CLI tests share: every run made with `tiny_config()` (and equal `--set`
values) reuses one compiled PPO update and one compiled evaluator per session."""

from __future__ import annotations

from helpers.paths import EXPERIMENTS
from kinetix_cli.config import ExperimentConfig, load_config

TRAIN_LEVELS = ["levels/s/rocket-car-jump.json", "levels/s/pad-to-pad.json"]
EVAL_LEVEL = "levels/s/rocket-car-jump.json"
TINY = [
    "levels.source=files",
    f"levels.files=[{', '.join(TRAIN_LEVELS)}]",
    "env.frame_skip=4",  # not the default 2: every consumer of a run must use the run's own environment
    "model.width=16",
    "model.actor_critic_layers=1",
    "ppo.num_envs=8",
    "ppo.num_steps=8",
    "ppo.num_minibatches=2",
    "ppo.update_epochs=1",
    "ppo.total_timesteps=384",  # 6 updates
    "run.checkpoint_every=2",
    "run.eval_every=4",  # evaluation during training at update 4 and after the last (6)
    f"run.eval_levels=[{EVAL_LEVEL}]",
    "run.eval_attempts=3",
]
"""`--set` values of the tiny run on top of experiments/cpu-small.yaml."""


def tiny_config(*overrides: str) -> ExperimentConfig:
    """experiments/cpu-small.yaml with `TINY` and then `overrides` applied."""
    return load_config(EXPERIMENTS / "cpu-small.yaml", [*TINY, *overrides])


def set_args(overrides: list[str]) -> list[str]:
    """`--set` command-line arguments for `overrides`."""
    return [arg for value in overrides for arg in ("--set", value)]
