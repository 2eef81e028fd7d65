"""Learning curves (`kinetix plot`): runs that differ only in their seed are one group drawn as a mean with a band,
the legend names what differs between groups, a run still writing its last line is read with a warning, and the
plotted numbers come out as JSON and CSV; bad input is one line and exit code 2."""

from __future__ import annotations

import csv
import json

import pytest

from helpers.cli import kinetix
from helpers.runs import copy_run
from kinetix_cli.errors import UserError
from kinetix_cli.viz.curves import draw, learning_curves, read_run


@pytest.fixture
def runs(tmp_path, tiny_run):
    """Three runs: two seeds of one experiment (returns 0.5 apart) and one at another learning rate."""
    return [
        copy_run(tiny_run, tmp_path / "seed-0"),
        copy_run(tiny_run, tmp_path / "seed-1", [("run.seed", 1)], shift=0.5),
        copy_run(tiny_run, tmp_path / "fast", [("ppo.lr", 0.001)]),
    ]


def test_seeds_are_one_group_with_a_band_and_the_legend_names_the_difference(runs):
    curves = learning_curves(runs, ["return", "eval_solve_rate"])
    assert [(c.metric, c.label, len(c.runs)) for c in curves] == [
        ("return", "ppo.lr=0.0003", 2),
        ("return", "ppo.lr=0.001", 1),
        ("eval_solve_rate", "ppo.lr=0.0003", 2),
        ("eval_solve_rate", "ppo.lr=0.001", 1),
    ]
    seeds = curves[0]
    assert len(seeds.x) == 6 and (seeds.high - seeds.low == pytest.approx(0.5, abs=1e-6))
    assert curves[2].x.tolist() == [256, 384]  # evaluations at updates 4 and 6 (64 steps each)

    figure = draw(curves)
    axes = figure.axes
    assert [ax.get_title() for ax in axes] == ["return", "eval_solve_rate"]
    for ax in axes:
        assert len(ax.get_lines()) == 2 and len(ax.collections) == 1  # one band: the group of two seeds
    legend = [t.get_text() for t in axes[0].get_legend().get_texts()]
    assert legend == ["ppo.lr=0.0003 (2 runs)", "ppo.lr=0.001"]


def test_group_by_a_key_and_time_on_x(runs):
    curves = learning_curves(runs, ["return"], x_axis="time", by=["run.seed"])
    assert sorted(c.label for c in curves) == ["run.seed=0", "run.seed=1"]
    assert all((c.x[1:] > c.x[:-1]).all() for c in curves)  # training seconds, increasing


def test_a_run_still_writing_is_read_up_to_its_last_whole_line(tmp_path, tiny_run):
    run = copy_run(tiny_run, tmp_path / "running")
    with (run / "metrics.jsonl").open("a") as f:
        f.write('{"update": 7, "ret')
    with pytest.warns(UserWarning, match="line 7 is incomplete"):
        assert len(read_run(run).lines) == 6
    text = (run / "metrics.jsonl").read_text()
    (run / "metrics.jsonl").write_text('{"torn\n' + text)
    with pytest.raises(UserError, match="line 1 is not JSON"):
        read_run(run)


def test_plot_writes_the_figure_and_its_numbers(capsys, tmp_path, runs):
    png, as_json, as_csv = tmp_path / "curves.png", tmp_path / "curves.json", tmp_path / "curves.csv"
    result = kinetix(capsys, "plot", *runs, "-o", png, "--metric", "return", "--json", as_json, "--csv", as_csv)
    assert result.code == 0, result.err
    assert png.read_bytes().startswith(b"\x89PNG")
    payload = json.loads(as_json.read_text())
    assert payload["format"] == "kinetix-curves/1" and len(payload["points"]) == 12  # 2 groups x 6 updates
    with as_csv.open() as f:
        rows = list(csv.DictReader(f))
    assert [float(r["mean"]) for r in rows] == [p["mean"] for p in payload["points"]]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["{tmp}"], "not a run directory"),
        (["{run}", "--metric", "nope"], "--metric: no run logged 'nope'"),
        (["{run}", "--group", "ppo.nope"], "--group: unknown config key 'ppo.nope'"),
        (["{run}", "--x", "hours"], "--x: unknown axis 'hours'"),
    ],
    ids=["not-a-run", "metric", "group", "x"],
)
def test_bad_input_is_one_line(capsys, tmp_path, tiny_run, args, message):
    args = [a.format(tmp=tmp_path, run=tiny_run) for a in args]
    line = kinetix(capsys, "plot", *args, "-o", tmp_path / "c.png").error_line
    assert message in line
    assert not (tmp_path / "c.png").exists()


def test_a_figure_needs_a_known_type(capsys, tmp_path, tiny_run):
    assert ".png, .svg or .pdf" in kinetix(capsys, "plot", tiny_run, "-o", tmp_path / "c.gif").error_line
