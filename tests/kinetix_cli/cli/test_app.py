"""The `kinetix` CLI through typer's runner: exit codes, messages, and the JSON it writes."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from helpers.levels import CAR
from kinetix_cli.cli.app import app, main
from kinetix_cli.errors import UserError
from kinetix_cli.levels.format import format_level_json
from kinetix_cli.tools.demo import run_demo

runner = CliRunner()


def _run_main(monkeypatch, capsys, *args):
    monkeypatch.setattr("sys.argv", ["kinetix", *args])
    with pytest.raises(SystemExit) as info:
        main()
    return info.value.code, capsys.readouterr()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["bench", "engine", "--size", "xl"], "--size: unknown size 'xl'"),
        (["bench", "engine", "--envs", "64,abc"], "--envs: expected comma-separated integers"),
        (["bench", "engine", "--envs", "0"], "--envs: expected integers >= 1"),
        (["bench", "engine", "--against", "box2d"], "--against: only 'jax2d'"),
        (["bench", "env", "--obs", "rgb"], "--obs: unknown observation 'rgb'"),
        (["validate", "no/such/level.json"], "no/such/level.json: no such file or folder"),
        (["render", "no/such/level.json", "-o", "x.png"], "no/such/level.json: no such file"),
    ],
)
def test_bad_flags_exit_2_with_one_line(monkeypatch, capsys, args, message):
    code, out = _run_main(monkeypatch, capsys, *args)
    assert code == 2
    assert message in out.err
    assert "Traceback" not in out.err and len(out.err.strip().splitlines()) == 1


@pytest.fixture
def car_file(tmp_path):
    path = tmp_path / "car.json"
    path.write_text(format_level_json(CAR))
    return path


def test_bad_level_file_exit_2_naming_file_and_field(monkeypatch, capsys, car_file):
    data = json.loads(car_file.read_text())
    data["bodies"][1]["radius"] = 0
    car_file.write_text(json.dumps(data))
    code, out = _run_main(monkeypatch, capsys, "validate", str(car_file))
    assert code == 2
    assert f"{car_file}: bodies[1] 'wheel': radius: must be > 0 and <= 5, got 0" in out.err
    assert "Traceback" not in out.err


def test_validate_render_and_rollout(tmp_path, car_file):
    result = runner.invoke(app, ["validate", str(car_file)])
    assert result.exit_code == 0 and "1 level file(s) valid" in result.output
    png = tmp_path / "out" / "car.png"
    result = runner.invoke(app, ["render", str(car_file), "-o", str(png), "--scale", "40"])
    assert result.exit_code == 0, result.output
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    result = runner.invoke(app, ["rollout", str(car_file), "--policy", "noop", "-o", str(tmp_path / "car.gif")])
    assert result.exit_code == 0, result.output
    assert "policy noop: timed out after 256 steps" in result.output
    assert (tmp_path / "car.gif").read_bytes()[:6] == b"GIF89a"
    result = runner.invoke(app, ["rollout", str(car_file), "--policy", "solution"])
    assert isinstance(result.exception, UserError)  # CAR ships no solution: main() turns this into exit 2
    assert "solution: the level ships no solution" in str(result.exception)


def test_bench_engine_writes_versioned_json(tmp_path):
    path = tmp_path / "bench.json"
    result = runner.invoke(
        app, ["bench", "engine", "--size", "s", "--envs", "2", "--steps", "2", "--min-time", "0", "--json", str(path)]
    )
    assert result.exit_code == 0, result.output
    data = json.loads(path.read_text())
    assert data["format"] == "kinetix-bench/1"
    (row,) = data["results"]
    assert row["engine"] == "kinetix" and row["envs"] == 2 and row["steps_per_s"] > 0
    assert data["versions"]["jax"]


def test_demo_car_drives_up_the_ramp():
    """In 3 s the car drives > 1.5 m right and climbs (its chassis rises > 5 cm)."""
    frames, _, rate = run_demo(seconds=3.0)
    assert frames[-1].x - frames[0].x > 1.5
    assert max(f.y for f in frames) - frames[0].y > 0.05
    assert rate > 0
