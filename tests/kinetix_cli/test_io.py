import json
import os

import pytest

from kinetix_cli.io import atomic_write, atomic_write_json, atomic_write_text


def test_new_file_gets_the_usual_permissions(tmp_path):
    mask = os.umask(0o022)
    try:
        atomic_write_text(tmp_path / "a" / "new.txt", "hello")
    finally:
        os.umask(mask)
    path = tmp_path / "a" / "new.txt"
    assert path.read_text() == "hello"
    assert path.stat().st_mode & 0o777 == 0o644


def test_rewrite_keeps_the_permissions(tmp_path):
    path = tmp_path / "level.json"
    path.write_text("old")
    path.chmod(0o640)
    atomic_write_text(path, "new")
    assert path.read_text() == "new"
    assert path.stat().st_mode & 0o777 == 0o640


def test_failed_write_keeps_the_old_file_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "results.json"
    path.write_text("old")

    def explode(f):
        f.write(b"half")
        raise RuntimeError("disk on fire")

    with pytest.raises(RuntimeError):
        atomic_write(path, explode)
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["results.json"]


def test_json_carries_its_format_first(tmp_path):
    path = tmp_path / "bench.json"
    atomic_write_json(path, {"results": [1]}, "kinetix-bench/1")
    data = json.loads(path.read_text())
    assert list(data) == ["format", "results"]
    assert data["format"] == "kinetix-bench/1"
