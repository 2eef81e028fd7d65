"""The suites by name: 's', 'm', 'l' find the installed levels from any folder, 'validation' and 'test' name the
protocol's folders (or say how to get them), a path that exists wins, and results name a shipped level as
levels/<size>/<file> wherever it is installed."""

from __future__ import annotations

from pathlib import Path

import pytest

from helpers.paths import LEVELS, REPO
from kinetix_cli.errors import UserError
from kinetix_cli.levels.files import level_paths
from kinetix_cli.levels.suites import SUITES, heldout_folder, resolve_suite, shown_path, suite_folder


def test_a_suite_name_is_the_shipped_folder_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for name in SUITES:
        assert sorted(p.name for p in level_paths([name])) == sorted(p.name for p in (LEVELS / name).glob("*.json"))
    assert suite_folder("s").samefile(LEVELS / "s")
    with pytest.raises(ValueError, match="the shipped suites are s, m, l"):
        suite_folder("xl")


def test_a_path_that_exists_wins_over_a_suite_of_its_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s").mkdir()
    assert resolve_suite("s") == [Path("s")] and Path("s").resolve() != suite_folder("s")


def test_the_validation_suite_is_held_out_generated_levels_and_ours_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    files = level_paths(["validation"])
    folders = [heldout_folder(size) for size in SUITES] + [suite_folder(size) for size in SUITES]
    assert resolve_suite("validation") == folders
    assert [len(list(f.glob("*.json"))) for f in folders[:3]] == [40, 40, 40]
    assert len(files) == 120 + sum(len(list((LEVELS / size).glob("*.json"))) for size in SUITES)
    assert shown_path(files[0]) == "levels/validation/s/validation-s-000.json"


def test_the_test_suite_is_the_papers_74_levels_or_says_how_to_get_them(tmp_path, monkeypatch):
    monkeypatch.chdir(REPO)
    assert len(level_paths(["test"])) == 74
    monkeypatch.chdir(tmp_path)
    with pytest.raises(UserError, match="--levels test: .*make reference-levels"):
        level_paths(["test"])


def test_results_name_shipped_levels_as_in_a_checkout(tmp_path):
    assert shown_path(suite_folder("m") / "car.json") == "levels/m/car.json"
    assert shown_path(suite_folder("m")) == "levels/m"
    assert shown_path(tmp_path / "mine.json") == str(tmp_path / "mine.json")
