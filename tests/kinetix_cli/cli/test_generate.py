"""`kinetix generate` and the level-set commands through the CLI: a set is written, rerunning changes nothing,
info/show/export read it; bad input is one line and exit code 2."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from kinetix_cli.cli.app import app, main
from kinetix_cli.levels.files import load_level

runner = CliRunner()
CHUNK = 32


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
