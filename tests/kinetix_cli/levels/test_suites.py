"""The shipped suites by name: 's', 'm', 'l' find the installed levels from any folder, a path that exists wins,
and results name a shipped level as levels/<size>/<file> wherever it is installed."""

from __future__ import annotations

from pathlib import Path

import pytest

from helpers.paths import LEVELS
from kinetix_cli.levels.files import level_paths
from kinetix_cli.levels.suites import SUITES, resolve_suite, shown_path, suite_folder


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
    assert resolve_suite("s") == Path("s") and Path("s").resolve() != suite_folder("s")


def test_results_name_shipped_levels_as_in_a_checkout(tmp_path):
    assert shown_path(suite_folder("m") / "car.json") == "levels/m/car.json"
    assert shown_path(suite_folder("m")) == "levels/m"
    assert shown_path(tmp_path / "mine.json") == str(tmp_path / "mine.json")
