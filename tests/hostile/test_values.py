"""Values are checked for meaning, not only type: every number finite and in a meaningful range (the range in the
message), in level files, the reference format, configs and flags; a run that diverges stops instead of saving NaN."""

from __future__ import annotations

import copy
import json
import math

import pytest

from helpers.cli import kinetix
from helpers.levels import CAR
from helpers.paths import REFERENCE_LEVELS
from helpers.runs import tiny_config
from kinetix_cli.errors import UserError
from kinetix_cli.rl import train as train_module
from kinetix_cli.rl.curricula import dr


def level_file(tmp_path, change, name="car.json"):
    data = copy.deepcopy(CAR)
    change(data)
    path = tmp_path / name
    path.write_text(json.dumps(data))
    return path


def set_(path, value):
    def change(data):
        node = data
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = value

    return change


BAD_LEVEL_VALUES = [
    (("bodies", 0, "density"), 1e39, "bodies[0] 'chassis': density: must be > 0 and <= 10000, got 1e+39"),
    (("bodies", 0, "density"), 10**400, "density: must be a finite number"),
    (("bodies", 0, "position"), [1e30, 1.0], "position: must be in [-15, 15], got 1e+30"),
    (("bodies", 1, "radius"), float("inf"), "radius: must be a finite number, got Infinity"),
    (("bodies", 1, "radius"), float("nan"), "radius: must be a finite number, got NaN"),
    (("bodies", 0, "velocity"), [0.0, -1e6], "velocity: must be in [-100, 100]"),
    (("params",), {"dt": 0}, "params: dt: must be > 0 and <= 0.1, got 0"),
    (("params",), {"dt": -0.01}, "params: dt: must be > 0 and <= 0.1, got -0.01"),
    (("params",), {"base_motor_power": -5}, "params: base_motor_power: must be in [0, 1e+06]"),
    (("gravity",), [0, 1e9], "gravity: must be in [-1000, 1000]"),
    (("thrusters", 0, "power"), 1e12, "power: must be in [0, 10000]"),
    (("joints", 0, "motor", "speed"), -101, "speed: must be in [-100, 100]"),
]


@pytest.mark.parametrize(("path", "value", "message"), BAD_LEVEL_VALUES, ids=lambda x: str(x)[:30])
def test_level_values_out_of_range_are_one_line(capsys, tmp_path, path, value, message):
    line = kinetix(capsys, "validate", level_file(tmp_path, set_(path, value))).error_line
    assert message in line and "car.json" in line


def test_reference_env_params_are_checked_too(capsys, tmp_path):
    data = json.loads((REFERENCE_LEVELS / "s" / "h0_weak_thrust.json").read_text())
    data["env_params"]["dt"] = 0.0
    (tmp_path / "ref.json").write_text(json.dumps(data))
    assert "params: dt: must be > 0 and <= 0.1, got 0" in kinetix(capsys, "validate", tmp_path / "ref.json").error_line


BAD_SETTINGS = [
    ("ppo.lr=.inf", "ppo.lr: expected a finite number, got inf"),
    ("ppo.lr=.nan", "ppo.lr: expected a finite number, got nan"),
    ("ppo.lr=2", "ppo.lr: must be > 0 and <= 1 (got 2.0)"),
    (f"run.seed={2**40}", "run.seed: must be >= 0 and <= 2147482623"),
    ("run.seed=-1", "run.seed: must be >= 0"),
    (f"env.max_steps={2**40}", "env.max_steps: must be >= 1 and <= 2147483647"),
    ("env.frame_skip=0", "env.frame_skip: must be >= 1 and <= 1000 (got 0)"),
    (f"ppo.num_envs={10**400}", "ppo.num_envs: must be >= 1"),
    ("model.heads=6", "model.heads: must be a multiple of 4"),
    ("ppo.max_grad_norm=0", "ppo.max_grad_norm: must be > 0"),
    ("env.observation=pixels", "model.name: 'pi-mlp' needs env.observation 'symbolic-entity', got 'pixels'"),
    ("curriculum.score_batch=5000", "curriculum.score_batch: must divide curriculum.score_levels"),
    ("curriculum.buffer_size=20000", "curriculum.buffer_size: must be <= curriculum.score_levels"),
    ("curriculum.score_attempts=0", "curriculum.score_attempts: must be >= 1 and <= 1024 (got 0)"),
    ("curriculum.temperature=0", "curriculum.temperature: must be > 0 and <= 100"),
    ("curriculum.replay_prob=1.5", "curriculum.replay_prob: must be >= 0 and <= 1"),
    ("curriculum.plr_score=regret", "curriculum.plr_score"),
    ("curriculum.edits=0", "curriculum.edits: must be >= 1 and <= 100 (got 0)"),
    ("curriculum.buffer_share=0", "curriculum.buffer_share: must be > 0 and <= 1"),
    ("curriculum.name=sfl", None),  # with buffer_share 0.001 below: no environment starts from the buffer
    ("clone.updates=5", "clone.updates: needs clone.levels (got 5)"),
    ("clone.coef=-1", "clone.coef: must be >= 0 and <= 1000 (got -1.0)"),
    ("clone.batch=0", "clone.batch: must be >= 1 and <= 65536 (got 0)"),
    ("clone.levels=nowhere", "clone.levels: is unused unless clone.updates or clone.coef (got 'nowhere')"),
]


@pytest.mark.parametrize(("setting", "message"), BAD_SETTINGS, ids=lambda x: str(x)[:24])
def test_config_values_out_of_range_are_one_line(capsys, tmp_path, setting, message):
    args = ["pretrain", "--config", "experiments/cpu-small.yaml", "--run-dir", tmp_path / "run", "--set", setting]
    if setting == "model.heads=6":
        args += ["--set", "model.name=transformer", "--set", "model.width=120"]
    if setting.startswith("curriculum.buffer_size"):
        args += ["--set", "curriculum.name=sfl"]  # SFL keeps the best of the levels it scores
    if message is None:
        args += ["--set", "curriculum.buffer_share=0.001"]
        message = "curriculum.buffer_share: 0.001 of ppo.num_envs 64 is no environment"
    line = kinetix(capsys, *args).error_line
    assert message in line and not (tmp_path / "run").exists()


BAD_FLAGS = [
    (["generate", "--count", "0", "--out", "{TMP}/s"], "--count"),
    (["generate", "--count", "4", "--seed", "-1", "--out", "{TMP}/s"], "--seed"),
    (["generate", "--count", "4", "--seed", str(2**40), "--out", "{TMP}/s"], "--seed"),
    (["generate", "--count", "4", "--random-max-rate", "nan", "--out", "{TMP}/s"], "--random-max-rate"),
    (["generate", "--count", "4", "--shard-size", str(2**40), "--out", "{TMP}/s"], "--shard-size"),
    (["bench", "engine", "--min-time", "inf"], "--min-time"),
    (["bench", "engine", "--envs", "99999999999"], "--envs"),
    (["eval", "{TMP}", "--attempts", "0"], "--attempts"),
    (["rollout", "levels/s/pad-to-pad.json", "--seed", str(2**40)], "--seed"),
    (["solve", "levels/s/pad-to-pad.json", "--population", "1"], "--population"),
    (["levels", "show", "{TMP}", "--grid", "100000", "-o", "{TMP}/x.png"], "--grid"),
]


@pytest.mark.parametrize(("args", "flag"), BAD_FLAGS, ids=lambda x: " ".join(x)[:30] if isinstance(x, list) else x)
def test_flag_values_out_of_range_are_one_line(capsys, tmp_path, args, flag):
    line = kinetix(capsys, *(a.format(TMP=tmp_path) for a in args)).error_line
    assert flag in line


def test_a_run_that_diverges_stops_without_saving(tmp_path, tiny_pool, monkeypatch):
    """NaN losses end the run with one line (exit 2) and no checkpoint of the diverged update."""
    real = dr.ppo_update

    def diverging(runner, env_params, levels, **static):
        runner, metrics = real(runner, env_params, levels, **static)
        return runner, metrics | {"loss": metrics["loss"] * math.nan}

    monkeypatch.setattr(dr, "ppo_update", diverging)
    with pytest.raises(UserError, match="update 1: loss not finite: training diverged"):
        train_module.train(tiny_config(), tmp_path / "run", pool=tiny_pool)
    assert not (tmp_path / "run" / "checkpoints" / "1").exists()
    assert (tmp_path / "run" / "metrics.jsonl").read_text() == ""
