"""Evaluations side by side (`kinetix compare`): levels and suites in rows, one column per eval file, the last
minus the first; a Markdown table, a bar chart with one bar per evaluation and row, and JSON; eval files of
another format or too few files are one line and exit code 2."""

from __future__ import annotations

import json

import pytest

from helpers.cli import kinetix
from kinetix_cli.constants import EVAL_FORMAT
from kinetix_cli.io import atomic_write_json
from kinetix_cli.viz.compare import compare, draw, markdown


def eval_file(path, rates: dict[str, float]):
    """An eval file as `kinetix eval --json` writes it, with these solve rates per level (one suite, `levels/s`)."""
    levels = [{"level": name, "suite": "levels/s", "size": "s", "solve_rate": r} for name, r in rates.items()]
    mean = sum(rates.values()) / len(rates)
    suites = {"levels/s": {"levels": len(rates), "solve_rate": mean}, "all": {"levels": len(rates), "solve_rate": mean}}
    atomic_write_json(
        path, {"policy": "run", "attempts": 20, "seed": 0, "levels": levels, "suites": suites}, EVAL_FORMAT
    )
    return path


@pytest.fixture
def files(tmp_path):
    (tmp_path / "dr").mkdir()
    (tmp_path / "sfl").mkdir()
    return [
        eval_file(tmp_path / "dr" / "eval.json", {"levels/s/a.json": 0.25, "levels/s/b.json": 0.5}),
        eval_file(tmp_path / "sfl" / "eval.json", {"levels/s/a.json": 0.75, "levels/s/c.json": 1.0}),
    ]


def test_levels_and_suites_side_by_side_with_the_difference(files):
    columns, rows = compare(files)
    assert columns == ["dr", "sfl"]  # same file names: their folders (runs) tell them apart
    assert [(r.kind, r.name, r.rates, r.difference) for r in rows] == [
        ("level", "levels/s/a.json", (0.25, 0.75), 0.5),
        ("level", "levels/s/b.json", (0.5, None), None),
        ("level", "levels/s/c.json", (None, 1.0), None),
        ("suite", "levels/s", (0.375, 0.875), 0.5),
        ("suite", "all", (0.375, 0.875), 0.5),
    ]
    table = markdown(columns, rows).splitlines()
    assert table[0] == "| level / suite | dr | sfl | sfl - dr |"
    assert table[2] == "| levels/s/a.json | 25.0% | 75.0% | +50.0 |"
    assert table[5] == "| **levels/s** (mean) | 37.5% | 87.5% | +50.0 |"
    ax = draw(columns, rows).axes[0]
    assert len(ax.patches) == 2 * 5  # one bar per evaluation and row (a missing rate is an empty bar)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == columns


def test_compare_prints_markdown_and_writes_a_chart_and_json(capsys, tmp_path, files):
    chart, as_json = tmp_path / "bars.png", tmp_path / "compare.json"
    result = kinetix(capsys, "compare", *files, "--markdown", "-o", chart, "--json", as_json)
    assert result.code == 0, result.err
    assert "| levels/s/a.json | 25.0% | 75.0% | +50.0 |" in result.out
    assert chart.read_bytes().startswith(b"\x89PNG")
    payload = json.loads(as_json.read_text())
    assert payload["format"] == "kinetix-compare/1" and payload["rows"][0]["difference"] == 0.5


def test_bad_input_is_one_line(capsys, tmp_path, files):
    assert "give two or more eval files" in kinetix(capsys, "compare", files[0]).error_line
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"format": "kinetix-curves/1", "points": []}))
    line = kinetix(capsys, "compare", files[0], other).error_line
    assert f"{other}: format: expected 'kinetix-eval/1', got 'kinetix-curves/1'" in line
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps({"format": "kinetix-eval/1", "levels": [{"level": "x"}], "suites": {}}))
    line = kinetix(capsys, "compare", files[0], broken).error_line
    assert f"{broken}: levels: every entry needs a level, a suite and a solve_rate" in line
