"""`kinetix generate` and the level-set commands through the CLI: a set is written, rerunning changes nothing,
info/show/export read it; in make test-all, two processes and two devices write the same set; bad input is one
line and exit code 2."""

from __future__ import annotations

import json

import jax
import numpy as np
import pytest
from typer.testing import CliRunner

from helpers.cli import kinetix
from helpers.levelsets import CHUNK, GENERATE_GROUP
from helpers.processes import FORCE_2, exact_env, processes, run_ok, start
from kinetix_cli.cli.app import app, main
from kinetix_cli.env.level import level_count
from kinetix_cli.levels import export
from kinetix_cli.levels.export import export_level
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.levelset import load_levelset

pytestmark = GENERATE_GROUP
runner = CliRunner()


GENERATE = ["generate", "--size", "s", "--count", "40", "--seed", "3", "--chunk", str(CHUNK), "--shard-size", "16"]


def files_of(folder) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """A set written by `kinetix generate` in this process (one device)."""
    out = tmp_path_factory.mktemp("generate") / "set"
    result = runner.invoke(app, [*GENERATE, "--out", str(out)])
    assert result.exit_code == 0, result.output
    return out


def test_generate_info_show_export(tmp_path, generated, capsys, monkeypatch, first_chunk):
    out, args = generated, GENERATE
    files = files_of(out)
    assert sorted(files) == ["manifest.json", "shard-00000.npz", "shard-00001.npz", "shard-00002.npz"]
    manifest = json.loads(files["manifest.json"])
    assert manifest["format"] == "kinetix-levelset/1" and manifest["count"] == 40
    assert manifest["settings"]["filters"] == {"noop": True, "random_attempts": 3, "random_max_rate": 0.5}
    # the set starts with the levels its first chunk kept, as the library makes that chunk again: deterministic
    _, (kept, _) = first_chunk
    count = level_count(kept)
    jax.tree.map(lambda a, b: np.testing.assert_array_equal(a[:count], b), load_levelset(out).levels, kept)

    again = runner.invoke(app, [*args, "--out", str(out)])  # a finished set: nothing to do, nothing changes
    assert again.exit_code == 0 and files_of(out) == files

    info = runner.invoke(app, ["levels", "info", str(out), "--json"])
    stats = json.loads(info.output)
    assert stats["statistics"]["levels"] == 40 and stats["generation"]["sampled"] >= 40

    assert runner.invoke(app, ["levels", "show", str(out), "--grid", "4", "-o", str(tmp_path / "g.png")]).exit_code == 0
    level_json = tmp_path / "level.json"
    assert runner.invoke(app, ["levels", "export", str(out), "--index", "39", "-o", str(level_json)]).exit_code == 0
    spec = load_level(level_json)
    assert spec.size == "s" and spec.description
    folder = tmp_path / "first"  # the first levels as a folder of level files, each as --index writes it
    assert runner.invoke(app, ["levels", "export", str(out), "--first", "40", "-o", str(folder)]).exit_code == 0
    written = sorted(folder.iterdir())
    assert [f.name for f in written] == [f"{out.name}-{i:05d}.json" for i in range(40)]
    assert written[39].read_bytes() == level_json.read_bytes()
    for wrong, says in (
        (["--first", "41"], "has 40"),
        (["--index", "1", "--first", "2"], "exactly one"),
        ([], "exactly one"),
    ):
        line = kinetix(capsys, "levels", "export", out, *wrong, "-o", tmp_path / "wrong").error_line
        assert says in line and not (tmp_path / "wrong").exists()

    def cannot_hold_level_3(level, static, *, name, description):
        if name.endswith(" 3"):
            raise ValueError("a fixed joint holding another angle")
        return export_level(level, static, name=name, description=description)

    monkeypatch.setattr(export, "export_level", cannot_hold_level_3)
    line = kinetix(capsys, "levels", "export", out, "--first", "5", "-o", tmp_path / "partial").error_line
    assert "level 3 cannot be written" in line and not (tmp_path / "partial").exists()  # not levels 0-2 either


@pytest.fixture(scope="module")
def generated_exact(tmp_path_factory):
    """The set written by `kinetix generate` in a new process on one device, compiled as outside the suite
    (`exact_env`): what 2 devices and 2 processes must write byte for byte."""
    out = tmp_path_factory.mktemp("generate-exact") / "set"
    run_ok([start([*GENERATE, "--out", out], exact_env())])
    return out


@pytest.mark.slow  # ~70 s: both processes compile the chunk program; multi-process training stays in make test
def test_two_processes_write_the_set_of_one_device(tmp_path, generated_exact):
    # each device computes whole chunks with the one-device program, so the set is the same byte for byte; shards
    # 0 and 2 are written by process 0, shard 1 by process 1, the manifest by process 0
    run_ok(processes([*GENERATE, "--out", tmp_path / "two-processes"], exact_env()))
    assert files_of(tmp_path / "two-processes") == files_of(generated_exact)


@pytest.mark.slow
def test_two_devices_write_the_set_of_one_device(tmp_path, generated_exact):
    run_ok([start([*GENERATE, "--out", tmp_path / "two-devices"], exact_env(), XLA_FLAGS=FORCE_2)])
    assert files_of(tmp_path / "two-devices") == files_of(generated_exact)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["generate", "--size", "xl", "--count", "4", "--out", "{tmp}/a"], "--size: unknown size 'xl'"),
        (["generate", "--count", "4", "--filter", "lucky", "--out", "{tmp}/a"], "--filter: unknown filter lucky"),
        (["levels", "info", "{tmp}/nothing"], "nothing"),
        (["generate", "--count", "4", "--seed", "2147482624", "--out", "{tmp}/a"], "--seed"),  # the validation's
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, monkeypatch, capsys, args, message):
    monkeypatch.setattr("sys.argv", ["kinetix", *(a.format(tmp=tmp_path) for a in args)])
    with pytest.raises(SystemExit) as info:
        main()
    err = capsys.readouterr().err
    assert info.value.code == 2 and message in err and len(err.strip().splitlines()) == 1
