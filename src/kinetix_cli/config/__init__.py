"""Typed experiment config: frozen dataclasses, loaded from YAML files in `experiments/`, overridden from the CLI.

Two modules: `settings` (the dataclasses, one per section, each checking its own fields with `fields`) and
`loader` (YAML in and out, `--set` overrides, suggestions for unknown keys). Everything public is here.

An experiment file has one mapping per section (`env`, `model`, `ppo`, `run`, `levels`, `curriculum`); every field
has a default except `ppo.total_timesteps`. `load_config(path, ["ppo.lr=3e-4"])` reads a file, applies `--set`
overrides and returns a validated `ExperimentConfig`; `save_config` writes the resolved config (every field, with a
`format: kinetix-experiment/1` line) that `load_config` reads back to an equal config.

Every mistake is a `ConfigError` (a `UserError`: one line, the CLI exits 2) naming the file or `--set`, the dotted
key and what was expected:

    experiments/x.yaml: unknown key 'ppo.learning_rate'; did you mean 'ppo.lr'?
    experiments/x.yaml: ppo.lr: expected a number, got 'fast' (str)

Numbers may be written `5e-5` or `1e6` (PyYAML alone reads those as strings); an integral float such as `5e9` is
accepted for an integer field. The choices of the string fields come from `engine.SIZES` and
`kinetix_cli.constants`, so they cannot drift from what the environment and the networks accept.
"""

from kinetix_cli.config.fields import ConfigError
from kinetix_cli.config.loader import config_to_dict, format_config, load_config, save_config
from kinetix_cli.config.settings import (
    CONFIG_FILENAME,
    CONFIG_FORMAT,
    SECTIONS,
    ActionKind,
    CloneSettings,
    CurriculumName,
    CurriculumSettings,
    EnvSettings,
    ExperimentConfig,
    LevelSettings,
    LevelSource,
    ModelName,
    ModelSettings,
    Observation,
    PLRScore,
    PPOSettings,
    RunSettings,
    Size,
    WandbMode,
)

__all__ = [
    "CONFIG_FILENAME",
    "CONFIG_FORMAT",
    "SECTIONS",
    "ActionKind",
    "CloneSettings",
    "ConfigError",
    "CurriculumName",
    "CurriculumSettings",
    "EnvSettings",
    "ExperimentConfig",
    "LevelSettings",
    "LevelSource",
    "ModelName",
    "ModelSettings",
    "Observation",
    "PLRScore",
    "PPOSettings",
    "RunSettings",
    "Size",
    "WandbMode",
    "config_to_dict",
    "format_config",
    "load_config",
    "save_config",
]
