"""Outputs never destroy: every command that writes checks its destination before the work starts, refuses
special files (FIFOs, devices) instead of replacing them, names the path in one line, and cleans temporaries."""

from __future__ import annotations

import errno
import json
import os
import stat
from pathlib import Path

import pytest

from helpers.cli import kinetix
from helpers.levelsets import small_levelset
from helpers.paths import REFERENCE_LEVELS

LEVEL = "levels/s/pad-to-pad.json"


@pytest.fixture(scope="module")
def levelset(tmp_path_factory):
    out = tmp_path_factory.mktemp("set") / "set"
    small_levelset(out)
    return out


# (arguments with {OUT} where the file goes)
FILE_WRITERS = [
    ["render", LEVEL, "-o", "{OUT}"],
    ["rollout", LEVEL, "--policy", "noop", "-o", "{OUT}"],
    ["levels", "sheet", LEVEL, "-o", "{OUT}"],
    ["levels", "show", "{SET}", "-o", "{OUT}"],
    ["levels", "export", "{SET}", "--index", "0", "-o", "{OUT}"],
    ["eval", "{RUN}", "--levels", LEVEL, "--json", "{OUT}"],
    ["bench", "engine", "--envs", "1", "--steps", "1", "--min-time", "0", "--json", "{OUT}"],
    ["bench", "env", "--envs", "1", "--json", "{OUT}"],
    ["bench", "train", "--envs", "4", "--json", "{OUT}"],
    ["bench", "generate", "--json", "{OUT}"],
    ["import", str(REFERENCE_LEVELS / "s"), "-o", "{TMP}/imported", "--report", "{OUT}"],
]
FOLDER_WRITERS = [
    ["generate", "--count", "4", "--out", "{OUT}"],
    ["pretrain", "--config", "experiments/cpu-small.yaml", "--run-dir", "{OUT}"],
    ["finetune", LEVEL, "--from", "none", "--config", "experiments/cpu-small.yaml", "--run-dir", "{OUT}"],
    ["import", str(REFERENCE_LEVELS / "s"), "-o", "{OUT}"],
]


def fill(args, out, tmp_path, levelset):
    return [a.format(OUT=out, TMP=tmp_path, SET=levelset, RUN=tmp_path / "no-run") for a in args]


@pytest.fixture
def fifo(tmp_path):
    path = tmp_path / "pipe"
    os.mkfifo(path)
    return path


@pytest.mark.parametrize("args", FILE_WRITERS, ids=lambda a: " ".join(a[:2]))
def test_a_fifo_is_refused_and_stays_a_fifo(capsys, tmp_path, fifo, levelset, args):
    line = kinetix(capsys, *fill(args, fifo, tmp_path, levelset)).error_line
    assert str(fifo) in line and "not a regular file" in line
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)


@pytest.mark.parametrize("args", FILE_WRITERS, ids=lambda a: " ".join(a[:2]))
def test_a_folder_where_a_file_goes_is_refused(capsys, tmp_path, levelset, args):
    folder = tmp_path / "folder"
    folder.mkdir()
    line = kinetix(capsys, *fill(args, folder, tmp_path, levelset)).error_line
    assert str(folder) in line and "is a folder" in line


@pytest.mark.parametrize("args", FILE_WRITERS[:3], ids=lambda a: " ".join(a[:2]))
def test_dev_null_and_an_empty_name_are_refused(capsys, tmp_path, levelset, args):
    assert "not a regular file" in kinetix(capsys, *fill(args, "/dev/null", tmp_path, levelset)).error_line
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    assert "is a folder" in kinetix(capsys, *fill(args, "", tmp_path, levelset)).error_line  # "" is "."


@pytest.mark.parametrize("args", FILE_WRITERS[:3], ids=lambda a: " ".join(a[:2]))
def test_a_file_in_place_of_a_parent_folder_is_refused(capsys, tmp_path, levelset, args):
    blocker = tmp_path / "blocker"
    blocker.write_text("mine")
    line = kinetix(capsys, *fill(args, blocker / "out.png", tmp_path, levelset)).error_line
    assert "cannot be created" in line and blocker.read_text() == "mine"


@pytest.mark.parametrize("args", FOLDER_WRITERS, ids=lambda a: a[0])
def test_a_file_where_a_folder_goes_is_refused_untouched(capsys, tmp_path, args):
    target = tmp_path / "target"
    target.write_text("mine")
    line = kinetix(capsys, *fill(args, target, tmp_path, None)).error_line
    assert str(target) in line and "not a folder" in line and target.read_text() == "mine"


def test_eval_checks_its_json_destination_before_evaluating(capsys, tmp_path):
    """The destination is refused before the run is even read (it used to fail after the whole evaluation)."""
    line = kinetix(capsys, "eval", tmp_path / "not-a-run", "--json", tmp_path).error_line
    assert "--json" in line and "is a folder" in line


def test_a_killed_writes_temporary_is_cleaned_by_the_next_write(capsys, tmp_path):
    out = tmp_path / "level.png"
    stale = tmp_path / ".level.png.x1y2z3.tmp"
    stale.write_bytes(b"half a png")
    assert kinetix(capsys, "render", LEVEL, "-o", out, "--scale", "20").code == 0
    assert out.read_bytes()[:4] == b"\x89PNG" and not stale.exists()


def test_import_refuses_two_sources_on_one_target_before_writing(capsys, tmp_path):
    """The paper's m/ and l/ folders both hold h1_car_left.json: one would overwrite the other."""
    out = tmp_path / "imported"
    line = kinetix(capsys, "import", REFERENCE_LEVELS / "m", REFERENCE_LEVELS / "l", "-o", out).error_line
    assert "h1_car_left.json" in line and "would both be written" in line
    assert not out.exists()


def test_solve_write_refuses_a_level_it_cannot_write(capsys, tmp_path):
    folder = tmp_path / "level.json"
    folder.mkdir()
    assert "is a folder" in kinetix(capsys, "solve", folder, "--write").error_line


def test_written_files_keep_their_format_tags(capsys, tmp_path):
    report = tmp_path / "report.json"
    result = kinetix(capsys, "import", REFERENCE_LEVELS / "s", "-o", tmp_path / "s", "--report", report)
    assert result.code == 0, result.err
    assert json.loads(report.read_text())["format"] == "kinetix-import-report/1"
    level = json.loads((tmp_path / "s" / "h0_weak_thrust.json").read_text())
    assert level["format"] == "kinetix-level/1"


def test_a_full_disk_is_one_line_and_keeps_the_old_file(capsys, tmp_path, monkeypatch):
    out = tmp_path / "level.png"
    out.write_bytes(b"the old picture")

    def no_space(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", no_space)
    line = kinetix(capsys, "render", LEVEL, "-o", out).error_line
    assert f"{out}: cannot write: No space left on device" in line
    assert out.read_bytes() == b"the old picture" and [p.name for p in tmp_path.iterdir()] == ["level.png"]


def test_a_read_only_folder_is_refused_before_the_work(capsys, tmp_path, monkeypatch):
    """Checked with os.access, so that it also holds when the tests run as root (where chmod cannot stop a write)."""
    locked = tmp_path / "locked"
    locked.mkdir()
    real_access = os.access
    monkeypatch.setattr(
        os, "access", lambda p, mode: not (Path(p) == locked and mode & os.W_OK) and real_access(p, mode)
    )
    assert f"{locked} is not writable" in kinetix(capsys, "render", LEVEL, "-o", locked / "x.png").error_line
    assert "is not writable" in kinetix(capsys, "generate", "--count", "4", "--out", locked).error_line
    assert list(locked.iterdir()) == []
