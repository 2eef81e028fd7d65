"""Run reports (`kinetix report`) of two seeds of the session's tiny run: the page parses and every file it shows
is beside it, the curves are one group with its band, the latest evaluation is a table with the level's picture
and a GIF of the agent; an earlier report is replaced, anything else refused; bad input is one line and exit
code 2. (The buffer section: tests/kinetix_cli/rl/curricula/test_sfl.py; a fine-tuned run: rl/test_agents.py;
the page in headless Chromium: slow, below.)"""

from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pytest
from PIL import Image

from helpers.cli import kinetix
from helpers.pages import read_report
from helpers.runs import EVAL_LEVEL, copy_run
from kinetix_cli.viz import report


@pytest.fixture(scope="module")
def seeds(tmp_path_factory, tiny_run):
    """Two runs that differ only in their seed (copies of the tiny run)."""
    folder = tmp_path_factory.mktemp("seeds")
    return [copy_run(tiny_run, folder / "seed-0"), copy_run(tiny_run, folder / "seed-1", [("run.seed", 1)])]


@pytest.fixture(scope="module")
def made(tmp_path_factory, seeds):
    """The report of both seeds, and the figure of its curves (the matplotlib object)."""
    out = tmp_path_factory.mktemp("reports") / "seeds"
    figures = []
    save = report.save_figure
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(report, "save_figure", lambda figure, path: figures.append(figure) or save(figure, path))
        report.write_report(seeds, out)
    return out, figures[0]


def test_a_report_of_two_seeds_shows_one_group_its_evaluation_and_the_agent(made, seeds):
    out, figure = made
    page, payload = read_report(out)
    assert [r["path"] for r in payload["runs"]] == [str(s) for s in seeds] and payload["groups"] == ["seed-0"]
    assert [ax.get_title() for ax in figure.axes] == ["eval_solve_rate", "solve_rate", "return"]
    for ax in figure.axes:
        assert len(ax.get_lines()) == 1 and len(ax.collections) == 1  # one group: its mean and its band over 2 seeds
    (level,) = payload["levels"]
    assert level["level"] == EVAL_LEVEL and len(level["solve_rates"]["seed-0"]["runs"]) == 2
    episode = level["episodes"]["seed-0"]
    assert episode["update"] == 6 and episode["ending"] in ("solved", "failed", "timed out")
    assert episode["length"] <= 200 and Image.open(out / episode["gif"]).n_frames == episode["length"] + 1
    assert sorted(page.refs) == sorted(["curves.png", "curves.json", level["picture"], episode["gif"]])
    text = " ".join(page.text)
    for shown in ("seed-0", "seed-1", "rocket", "jax", "ppo:", "Latest evaluation", "Versions"):
        assert shown in text, shown


def test_group_by_a_key_gives_a_column_per_group_and_escapes_text(capsys, tmp_path, seeds):
    odd = copy_run(seeds[0], tmp_path / "lr <b>", [("ppo.lr", 0.001)])
    out = tmp_path / "report"
    assert kinetix(capsys, "report", *seeds, odd, "-o", out, "--group", "ppo.lr", "--no-gifs").code == 0
    page, payload = read_report(out)
    assert payload["groups"] == ["ppo.lr=0.0003", "ppo.lr=0.001"]
    rates = payload["levels"][0]["solve_rates"]
    assert [len(rates[g]["runs"]) for g in payload["groups"]] == [2, 1]
    headers = " ".join(page.text)
    assert "solve rate: ppo.lr=0.0003 (2 runs)" in headers and "solve rate: ppo.lr=0.001" in headers
    # the folder name is text, not markup: the only <b> are the mean row's label and its two group means
    assert page.tags["b"] == 3 and "lr <b>" in headers


def test_a_report_is_replaced_and_other_folders_are_refused(capsys, tmp_path, seeds, made):
    out = tmp_path / "again"
    shutil.copytree(made[0], out)
    (out / "stale.png").write_bytes(b"")
    assert kinetix(capsys, "report", seeds[0], "-o", out, "--no-gifs").code == 0
    _, payload = read_report(out)
    assert not (out / "stale.png").exists() and not (out / "episodes").exists()
    assert [r["path"] for r in payload["runs"]] == [str(seeds[0])]
    assert list(tmp_path.iterdir()) == [out]  # nothing left beside it

    other = tmp_path / "notes"
    other.mkdir()
    (other / "mine.txt").write_text("keep me")
    assert "not a report folder" in kinetix(capsys, "report", seeds[0], "-o", other).error_line
    assert (other / "mine.txt").read_text() == "keep me"


def test_a_run_without_a_checkpoint_yet_or_its_level_files_is_reported_with_notes(capsys, tmp_path, seeds):
    early = tmp_path / "early"
    shutil.copytree(seeds[0], early)
    shutil.rmtree(early / "checkpoints")
    evaluation = early / "evaluations" / "6.json"
    record = json.loads(evaluation.read_text())
    record["levels"].append(record["levels"][0] | {"level": "elsewhere/gone.json"})  # evaluated from another folder
    evaluation.write_text(json.dumps(record))
    result = kinetix(capsys, "report", early, "-o", tmp_path / "report")
    _, payload = read_report(tmp_path / "report")
    assert result.code == 0 and "no checkpoint yet" in result.out and "gone.json: level file not found" in result.out
    assert [(e["picture"], e["episodes"]) for e in payload["levels"]] == [("levels/0.png", {}), (None, {})]


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--eval", "{curves}"], "format: expected 'kinetix-eval/1', got 'kinetix-curves/1'"),
        (["--eval", "{curves}", "--eval", "{curves}"], "--eval: give one eval file per run (1 runs, 2 files)"),
        (["--group", "ppo.nothing"], "--group: unknown config key 'ppo.nothing'"),
    ],
)
def test_bad_input_is_one_line(capsys, tmp_path, seeds, made, extra, message):
    args = [a.format(curves=made[0] / "curves.json") for a in extra]
    assert message in kinetix(capsys, "report", seeds[0], "-o", tmp_path / "r", *args).error_line
    assert "not a run directory" in kinetix(capsys, "report", tmp_path, "-o", tmp_path / "r").error_line
    assert not (tmp_path / "r").exists()


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("chromium") is None, reason="needs Debian's chromium (apt install chromium)")
def test_the_page_renders_in_headless_chromium(made, tmp_path):
    shot = tmp_path / "page.png"
    command = ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"]
    command += ["--window-size=1280,2000", f"--screenshot={shot}", (made[0] / "index.html").as_uri()]
    subprocess.run(command, check=True, capture_output=True, timeout=120)
    pixels = np.asarray(Image.open(shot).convert("RGB"))
    assert pixels.shape == (2000, 1280, 3)
    assert (pixels < 128).any(axis=2).mean() > 0.01  # text and figures drawn, not a blank page
    shutil.copy(shot, made[0].parent / "page.png")  # kept for a person to look at (pytest's basetemp)
