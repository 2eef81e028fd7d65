"""The tiny training run most RL and CLI tests share: every run made with `tiny_config()` (and equal `--set`
values) reuses one compiled PPO update and one compiled evaluator per session."""

from __future__ import annotations

import json
import shutil

import pytest
import yaml

from helpers.paths import EXPERIMENTS, REFERENCE_LEVELS
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


LEARN_LEVEL = REFERENCE_LEVELS / "s" / "h3_point_the_thruster.json"  # PPO from scratch: ~100% within 20K steps
SFL = [
    "curriculum.name=sfl",
    "curriculum.score_levels=8",
    "curriculum.score_batch=4",
    "curriculum.score_steps=16",
    "curriculum.score_attempts=2",
    "curriculum.buffer_size=4",
    "curriculum.refresh_every=2",
    "curriculum.buffer_share=0.5",
    f"levels.files=[{LEARN_LEVEL}, {LEARN_LEVEL}]",  # two copies: the tiny run's pool shape, so its compiles are shared
    "ppo.total_timesteps=19200",  # 300 updates of 8 envs x 8 steps
    "run.checkpoint_every=148",  # checkpoints 148, 296 and the last, 300: a resume from 296 runs 4 updates
    "run.eval_every=0",
]
"""`--set` values of the tiny SFL run, on top of `TINY`: the learning smoke test and the SFL run tests share it."""


SFL_RUN_GROUP = pytest.mark.xdist_group("sfl-run")
"""`pytestmark` of the modules that use the session's tiny SFL run: `make test` (xdist, `--dist loadgroup`) runs them
in one worker, which makes the run once."""


def sfl_config(*overrides: str) -> ExperimentConfig:
    """The tiny SFL run's configuration (`TINY`, `SFL`, then `overrides`)."""
    return tiny_config(*SFL, *overrides)


def set_args(overrides: list[str]) -> list[str]:
    """`--set` command-line arguments for `overrides`."""
    return [arg for value in overrides for arg in ("--set", value)]


def copy_run(source, dest, settings=(), shift=0.0):
    """A copy of the run `source` with config `settings` ((section.key, value), ...) and every `return` + shift."""
    shutil.copytree(source, dest)
    config = yaml.safe_load((dest / "config.yaml").read_text())
    for key, value in settings:
        section, name = key.split(".")
        config[section][name] = value
    (dest / "config.yaml").write_text(yaml.safe_dump(config))
    lines = [json.loads(line) for line in (dest / "metrics.jsonl").read_text().splitlines()]
    for line in lines:
        line["return"] += shift
    (dest / "metrics.jsonl").write_text("".join(json.dumps(line) + "\n" for line in lines))
    return dest
