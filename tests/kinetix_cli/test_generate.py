"""`kinetix generate` and the level-set commands: filters really filter, sets are reproducible, bad input is
one line and exit code 2."""

from __future__ import annotations

import json

import jax
import numpy as np
import pytest
from typer.testing import CliRunner

from engine import SIZES
from kinetix_cli.cli import app, main
from kinetix_cli.env import EnvConfig, EnvParams
from kinetix_cli.errors import UserError
from kinetix_cli.generate import FilterConfig, generate_chunk, make_config, parse_filters
from kinetix_cli.level_file import load_level
from kinetix_cli.solve import play

runner = CliRunner()
CHUNK = 32


@pytest.fixture(scope="session")
def chunk():
    config = make_config("s", CHUNK)
    return config, generate_chunk(config, seed=3, index=0)


def test_chunks_are_deterministic_and_counted(chunk):
    config, (levels, stats) = chunk
    again, _ = generate_chunk(config, seed=3, index=0)
    jax.tree.map(np.testing.assert_array_equal, levels, again)
    kept = levels.bindings.motor.shape[0]
    dropped = stats["dropped_invalid"] + stats["dropped_noop"] + stats["dropped_random"]
    assert stats["sampled"] == CHUNK and kept + dropped == CHUNK and kept > 0


def test_kept_levels_are_not_solved_by_doing_nothing(chunk):
    _, (levels, _) = chunk
    horizon = int(EnvParams().max_steps)
    noop = np.zeros((levels.bindings.motor.shape[0], horizon, 6), np.int32)
    assert not play(EnvConfig(SIZES["s"]), EnvParams(), levels, noop).solved.any()


def test_filter_flags():
    assert parse_filters("noop,random") == (True, True)
    assert parse_filters("none") == (False, False)
    with pytest.raises(UserError, match="--filter"):
        parse_filters("noop,lucky")
    with pytest.raises(UserError, match="--random-max-rate"):
        FilterConfig(random_max_rate=2.0)


def test_generate_info_show_export(tmp_path):
    out = tmp_path / "set"
    args = ["generate", "--size", "s", "--count", "40", "--seed", "3", "--chunk", str(CHUNK), "--shard-size", "16"]
    result = runner.invoke(app, [*args, "--out", str(out)])
    assert result.exit_code == 0, result.output
    files = {p.name: p.read_bytes() for p in out.iterdir()}
    assert sorted(files) == ["manifest.json", "shard-00000.npz", "shard-00001.npz", "shard-00002.npz"]
    manifest = json.loads(files["manifest.json"])
    assert manifest["format"] == "kinetix-levelset/1" and manifest["count"] == 40
    assert manifest["settings"]["filters"] == {"noop": True, "random_attempts": 3, "random_max_rate": 0.5}

    again = runner.invoke(app, [*args, "--out", str(out)])  # a finished set: nothing to do, nothing changes
    assert again.exit_code == 0 and {p.name: p.read_bytes() for p in out.iterdir()} == files

    info = runner.invoke(app, ["levels", "info", str(out), "--json"])
    stats = json.loads(info.output)
    assert stats["statistics"]["levels"] == 40 and stats["generation"]["sampled"] >= 40

    assert runner.invoke(app, ["levels", "show", str(out), "--grid", "4", "-o", str(tmp_path / "g.png")]).exit_code == 0
    level_json = tmp_path / "level.json"
    assert runner.invoke(app, ["levels", "export", str(out), "--index", "39", "-o", str(level_json)]).exit_code == 0
    spec = load_level(level_json)
    assert spec.size == "s" and spec.description


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["generate", "--size", "xl", "--count", "4", "--out", "{tmp}/a"], "--size: unknown size 'xl'"),
        (["generate", "--count", "4", "--filter", "lucky", "--out", "{tmp}/a"], "--filter: unknown filter lucky"),
        (["levels", "info", "{tmp}/nothing"], "nothing"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, monkeypatch, capsys, args, message):
    monkeypatch.setattr("sys.argv", ["kinetix", *(a.format(tmp=tmp_path) for a in args)])
    with pytest.raises(SystemExit) as info:
        main()
    err = capsys.readouterr().err
    assert info.value.code == 2 and message in err and len(err.strip().splitlines()) == 1


def test_level_statistics_count_what_the_levels_hold():
    from kinetix_cli.level import stack_levels
    from kinetix_cli.levelset_stats import level_statistics

    # rocket-car-jump: 1 polygon, 2 circles, 1 motor joint, 1 thruster; pad-to-pad: 1 polygon, 2 circles, 1 thruster
    files = ["levels/s/rocket-car-jump.json", "levels/s/pad-to-pad.json"]
    levels = jax.device_get(stack_levels([load_level(f).build(SIZES["s"]) for f in files]))
    stats = level_statistics("s", levels)
    per = stats["per level"]
    assert stats["levels"] == 2
    assert per["polygons"] == {"mean": 1.0, "min": 1, "max": 1} and per["circles"]["mean"] == 2.0
    assert per["motors"] == {"mean": 0.5, "min": 0, "max": 1} and per["thrusters"]["min"] == 1
    assert stats["levels with a motor"] == 1 and stats["levels with a thruster"] == 2
    assert stats["floor role"]["red"] == 1  # pad-to-pad's floor is red
