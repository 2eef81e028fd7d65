"""The `kinetix` CLI through typer's runner: exit codes, messages, and the JSON it writes."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from kinetix_cli.cli import app, main
from kinetix_cli.demo import run_demo

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
        (["bench", "engine", "--envs", "0"], "--envs: expected positive integers"),
        (["bench", "engine", "--against", "box2d"], "--against: only 'jax2d'"),
    ],
)
def test_bad_flags_exit_2_with_one_line(monkeypatch, capsys, args, message):
    code, out = _run_main(monkeypatch, capsys, *args)
    assert code == 2
    assert message in out.err
    assert "Traceback" not in out.err and len(out.err.strip().splitlines()) == 1


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
