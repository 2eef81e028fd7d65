"""Experiment configs: every shipped file loads, save/load round-trips, and every mistake is a one-line ConfigError."""

import dataclasses
import typing
from pathlib import Path

import pytest

from helpers.paths import EXPERIMENTS
from kinetix_cli.config import (
    CONFIG_FORMAT,
    SECTIONS,
    ConfigError,
    CurriculumSettings,
    EnvSettings,
    ExperimentConfig,
    LevelSettings,
    ModelSettings,
    PPOSettings,
    RunSettings,
    config_to_dict,
    load_config,
    save_config,
)
from kinetix_cli.errors import UserError

EXPERIMENTS = EXPERIMENTS
REPO = EXPERIMENTS.parent


def write(tmp_path, text: str, name: str = "exp.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


MINIMAL = "ppo:\n  total_timesteps: 1_000_000\n"


def error_of(path, overrides=()) -> str:
    with pytest.raises(ConfigError) as info:
        load_config(path, list(overrides))
    message = str(info.value)
    assert "\n" not in message
    assert isinstance(info.value, UserError) and info.value.exit_code == 2
    return message


# ------------------------------------------------------------------------------------------------ shipped files


@pytest.mark.parametrize("path", sorted(EXPERIMENTS.glob("*.yaml")), ids=lambda p: p.name)
def test_every_experiment_file_loads_and_has_a_comment_header(path):
    config = load_config(path, [])
    assert isinstance(config, ExperimentConfig)
    assert path.read_text().startswith("# ")
    for file in config.levels.files:
        assert (REPO / file).is_file(), file


def test_the_expected_experiment_files_exist_with_reference_settings():
    names = {p.stem for p in EXPERIMENTS.glob("*.yaml")}
    assert {"pretrain-s", "pretrain-m", "pretrain-l", "finetune", "cpu-small", "cpu-plr"} <= names
    budget = 10**12
    reference = PPOSettings(total_timesteps=budget)  # the defaults are the reference's
    for size in "sml":
        config = load_config(EXPERIMENTS / f"pretrain-{size}.yaml", [])
        assert config.env.size == size
        assert (config.model.name, config.env.observation, config.levels.source) == (
            "transformer",
            "symbolic-entity",
            "fresh",
        )
        assert config.curriculum == CurriculumSettings(name="sfl")  # the defaults are the reference's SFL
        assert config.model == ModelSettings()
        assert dataclasses.replace(config.ppo, total_timesteps=budget) == reference
    finetune = load_config(EXPERIMENTS / "finetune.yaml", [])
    pretrain = load_config(EXPERIMENTS / "pretrain-l.yaml", [])
    assert finetune.levels.source == "files" and finetune.levels.files
    assert dataclasses.replace(finetune.ppo, total_timesteps=budget) == dataclasses.replace(
        pretrain.ppo, total_timesteps=budget
    )
    assert finetune.ppo.total_timesteps < pretrain.ppo.total_timesteps
    small = load_config(EXPERIMENTS / "cpu-small.yaml", [])
    assert small.ppo.batch_size <= 4096 and small.ppo.total_timesteps <= 1_000_000


def test_choices_are_the_engines_sizes_and_the_constants():
    """The string fields accept exactly the names the engine and the environment define (one source each)."""
    from engine import SIZES
    from kinetix_cli.constants import ACTION_TYPES, MODEL_NAMES, OBSERVATION_TYPES

    env, model = typing.get_type_hints(EnvSettings), typing.get_type_hints(ModelSettings)
    assert typing.get_args(env["size"]) == tuple(SIZES) == ("s", "m", "l")
    assert typing.get_args(env["observation"]) == OBSERVATION_TYPES
    assert typing.get_args(env["action"]) == ACTION_TYPES
    assert typing.get_args(model["name"]) == MODEL_NAMES


def test_transformer_heads_must_fill_the_attention_channels():
    with pytest.raises(ConfigError, match="model.heads: must be a multiple of 4"):
        ModelSettings(name="transformer", width=120, heads=6)
    assert ModelSettings(name="pi-mlp", width=120, heads=6).heads == 6  # only the transformer has heads


def test_every_field_is_documented():
    for cls in [*SECTIONS.values(), ExperimentConfig]:
        for field in dataclasses.fields(cls):
            assert f"    {field.name}: " in cls.__doc__, f"{cls.__name__}.{field.name}"


# ------------------------------------------------------------------------------------------------ round trip


@pytest.mark.parametrize("name", ["pretrain-m.yaml", "finetune.yaml", "cpu-small.yaml"])
def test_save_then_load_gives_an_equal_config(tmp_path, name):
    config = load_config(EXPERIMENTS / name, ["run.seed=7", "ppo.anneal_lr=true"])
    path = save_config(config, tmp_path / "run" / "config.yaml")
    assert path.read_text().splitlines()[1] == f"format: {CONFIG_FORMAT}"
    assert load_config(path, []) == config
    assert config_to_dict(load_config(path, [])) == config_to_dict(config)


def test_defaults_fill_missing_sections_and_fields(tmp_path):
    config = load_config(write(tmp_path, MINIMAL + "levels:\n"), [])
    assert config == ExperimentConfig(ppo=PPOSettings(total_timesteps=1_000_000))
    assert (config.env, config.run, config.levels) == (EnvSettings(), RunSettings(), LevelSettings())
    assert config.run.wandb == "off" and config.run.eval_attempts == 50
    assert config.ppo.num_updates == 1_000_000 // (2048 * 64)
    assert config.ppo.minibatch_size == 2048 * 64 // 32


def test_yaml_1_2_numbers_and_booleans(tmp_path):
    text = "ppo:\n  total_timesteps: 5e9\n  lr: 3e-4\n  adam_eps: 1E-8\n  anneal_lr: True\nrun:\n  wandb: off\n"
    config = load_config(write(tmp_path, text), [])
    assert config.ppo.total_timesteps == 5_000_000_000 and isinstance(config.ppo.total_timesteps, int)
    assert config.ppo.lr == 3e-4 and config.ppo.adam_eps == 1e-8 and config.ppo.anneal_lr is True
    assert config.run.wandb == "off"


# ------------------------------------------------------------------------------------------------ overrides


def test_overrides_apply_and_are_typed(tmp_path):
    path = write(tmp_path, MINIMAL)
    config = load_config(
        path,
        [
            "ppo.lr=3e-4",
            "ppo.num_envs=64",
            "ppo.num_minibatches=4",
            "ppo.gamma=1",
            "ppo.anneal_lr=true",
            "env.size=s",
            "run.wandb=offline",
            "levels.source=files",
            "levels.files=[a.json, b.json]",
            "run.init_from=runs/x/ckpt",
        ],
    )
    assert config.ppo.lr == 3e-4 and config.ppo.num_envs == 64 and config.ppo.anneal_lr is True
    assert config.ppo.gamma == 1.0 and isinstance(config.ppo.gamma, float)
    assert config.env.size == "s" and config.run.wandb == "offline"
    assert config.levels.files == ("a.json", "b.json") and config.run.init_from == "runs/x/ckpt"


def test_later_overrides_win_and_can_supply_a_required_key(tmp_path):
    path = write(tmp_path, "env:\n  size: l\n")
    config = load_config(path, ["ppo.total_timesteps=1e6", "run.seed=1", "run.seed=2"])
    assert config.ppo.total_timesteps == 1_000_000 and config.run.seed == 2 and config.env.size == "l"


@pytest.mark.parametrize(
    ("override", "expected"),
    [
        ("ppo.learning_rate=3e-4", "--set: unknown key 'ppo.learning_rate'; did you mean 'ppo.lr'"),
        ("ppo.seed=3", "--set: unknown key 'ppo.seed'; did you mean 'run.seed'"),
        ("optim.lr=3e-4", "--set: unknown key 'optim.lr'; did you mean 'ppo.lr'"),
        ("ppo.lr", "--set ppo.lr: expected KEY=VALUE"),
        ("ppo.lr=fast", "--set: ppo.lr: expected a finite number, got 'fast' (str)"),
        ("ppo.num_envs=12.5", "--set: ppo.num_envs: expected an integer, got 12.5 (float)"),
        ("ppo.anneal_lr=1", "--set: ppo.anneal_lr: expected true or false, got 1 (int)"),
        ("env.size=xl", "--set: env.size: expected one of 's', 'm', 'l', got 'xl' (str)"),
        ("ppo.lr=[1", "--set ppo.lr: the value is not valid YAML"),
        ("format=x", "--set: unknown key 'format'"),
        ("run.seed=2147482624", "run.seed: must be >= 0 and <= 2147482623"),  # the validation suite's seeds
    ],
)
def test_bad_overrides_name_set_and_the_key(tmp_path, override, expected):
    assert expected in error_of(write(tmp_path, MINIMAL), [override])


def test_an_override_that_breaks_validation_is_named(tmp_path):
    message = error_of(write(tmp_path, MINIMAL), ["ppo.num_minibatches=7"])
    assert "with --set ppo.num_minibatches=7" in message and "ppo.num_minibatches" in message
    assert "not divisible" in message
    message = error_of(write(tmp_path, MINIMAL), ["ppo.total_timesteps=100"])
    assert "ppo.total_timesteps: is less than one update (num_envs * num_steps = 2048 * 64 = 131072)" in message


# ------------------------------------------------------------------------------------------------ file errors


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (MINIMAL + "  learning_rate: 3e-4\n", "unknown key 'ppo.learning_rate'; did you mean 'ppo.lr'?"),
        (MINIMAL + "  ent_coeff: 0.1\n", "unknown key 'ppo.ent_coeff'; did you mean 'ppo.ent_coef'?"),
        (MINIMAL + "enviroment:\n  size: s\n", "unknown key 'enviroment'; did you mean 'env'?"),
        (MINIMAL + "lr: 3e-4\n", "unknown key 'lr'; did you mean 'ppo.lr'?"),
        (MINIMAL + "optimiser:\n  lr: 3e-4\n", "unknown key 'optimiser'; valid sections: env, model, ppo, run, levels"),
        ("ppo:\n  timesteps: 1e6\n", "unknown key 'ppo.timesteps'; did you mean 'ppo.total_timesteps'?"),
    ],
)
def test_unknown_keys_are_named_with_a_suggestion(tmp_path, text, expected):
    path = write(tmp_path, text)
    message = error_of(path)
    assert message.startswith(f"{path}: ") and expected in message


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("  lr: fast\n", "ppo.lr: expected a finite number, got 'fast' (str)"),
        ("  num_envs: '64'\n", "ppo.num_envs: expected an integer, got '64' (str)"),
        ("  num_envs: true\n", "ppo.num_envs: expected an integer, got True (bool)"),
        ("  normalise_advantages: yes\n", "ppo.normalise_advantages: expected true or false, got 'yes' (str)"),
        (
            "env:\n  observation: entity\n",
            "env.observation: expected one of 'symbolic-flat', 'symbolic-entity', 'pixels'",
        ),
        ("levels:\n  source: files\n  files: a.json\n", "levels.files: expected a list of strings, got 'a.json'"),
        ("levels:\n  source: files\n  files: [a.json, 3]\n", "levels.files[1]: expected a string, got 3 (int)"),
        ("run:\n  init_from: 5\n", "run.init_from: expected a string or null, got 5 (int)"),
        ("env: s\n", "env: expected a mapping of its fields, got 's' (str)"),
    ],
)
def test_wrong_types_name_file_key_expected_type_and_value(tmp_path, text, expected):
    path = write(tmp_path, MINIMAL + text)
    message = error_of(path)
    assert message.startswith(f"{path}: ") and expected in message


def test_missing_file_bad_yaml_and_bad_top_level_name_the_file(tmp_path):
    assert "no such experiment file" in error_of(tmp_path / "nope.yaml")
    assert error_of(tmp_path / "nope.yaml").startswith(str(tmp_path / "nope.yaml"))
    bad = write(tmp_path, "ppo: [1, 2\n", "bad.yaml")
    assert error_of(bad).startswith(f"{bad}: invalid YAML")
    dup = write(tmp_path, MINIMAL + "  lr: 1e-4\n  lr: 2e-4\n", "dup.yaml")
    assert "duplicate key 'lr'" in error_of(dup)
    listed = write(tmp_path, "- 1\n- 2\n", "list.yaml")
    assert error_of(listed).startswith(f"{listed}: expected a mapping of sections")
    assert "missing required key 'ppo.total_timesteps'" in error_of(write(tmp_path, "", "empty.yaml"))
    assert "format: expected 'kinetix-experiment/1'" in error_of(write(tmp_path, "format: other/2\n" + MINIMAL))


# ------------------------------------------------------------------------------------------------ validation


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "  num_envs: 10\n  num_steps: 3\n  num_minibatches: 4\n",
            "num_envs * num_steps = 10 * 3 = 30 is not divisible",
        ),
        ("  num_envs: 0\n", "ppo.num_envs: must be >= 1"),
        ("  gamma: 1.5\n", "ppo.gamma: must be >= 0 and <= 1 (got 1.5)"),
        ("  lr: 0\n", "ppo.lr: must be > 0"),
        ("env:\n  frame_skip: 0\n", "env.frame_skip: must be >= 1"),
        ("model:\n  width: 100\n", "model.heads: width 100 is not divisible by heads"),
        ("model:\n  name: flat-mlp\n", "model.name: 'flat-mlp' needs env.observation 'symbolic-flat' or 'pixels'"),
        ("env:\n  observation: pixels\n", "model.name: 'transformer' needs env.observation 'symbolic-entity'"),
        ("run:\n  eval_attempts: 0\n", "run.eval_attempts: must be >= 1"),
        ("run:\n  minutes: -1\n", "run.minutes: must be >= 0"),
        ("levels:\n  source: levelset\n", "levels.levelset: is required when levels.source is 'levelset'"),
        ("levels:\n  source: files\n", "levels.files: must list at least one level file"),
        ("levels:\n  files: [a.json]\n", "levels.files: is only used when levels.source is 'files'"),
        ("levels:\n  pool_size: 0\n", "levels.pool_size: must be >= 1"),
        ("levels:\n  fresh_like: [s]\n", "levels.fresh_like: is only used when levels.source is 'fresh'"),
        ("levels:\n  source: fresh\n  fresh_like: [s, xl]\n", "levels.fresh_like: names no size ['xl']"),
        (
            "env:\n  size: m\nlevels:\n  source: fresh\n  fresh_like: [s, l]\n",
            "levels.fresh_like: ['l'] are larger than env.size 'm'",
        ),
    ],
)
def test_validation_errors_are_clear(tmp_path, text, expected):
    path = write(tmp_path, MINIMAL + text)
    message = error_of(path)
    assert message.startswith(f"{path}: ") and expected in message


def test_dataclasses_validate_when_built_in_code():
    with pytest.raises(ConfigError, match="ppo.num_minibatches"):
        PPOSettings(total_timesteps=10**9, num_minibatches=3)
    with pytest.raises(ConfigError, match="env.size: expected one of"):
        EnvSettings(size="xl")
    with pytest.raises(dataclasses.FrozenInstanceError):
        EnvSettings().size = "s"
    assert PPOSettings(total_timesteps=10**9, lr=1).lr == 1.0  # ints are normalised to floats
    assert LevelSettings(source="files", files=["a.json"]).files == ("a.json",)  # lists to tuples (hashable)
