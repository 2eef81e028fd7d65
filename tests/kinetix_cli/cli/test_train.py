"""The training commands through the CLI on the tiny run: eval, finetune and rollout --policy use the run's own
environment; eval takes the reference's level folders as they are."""

from __future__ import annotations

import json
import re

import pytest
from typer.testing import CliRunner

from helpers.levels import FALL
from helpers.paths import REFERENCE_LEVELS
from helpers.runs import EVAL_LEVEL, TINY, TRAIN_LEVELS, set_args
from kinetix_cli.cli.app import app, main
from kinetix_cli.config import load_config

runner = CliRunner()


def test_eval_writes_versioned_results(tmp_path, tiny_run):
    out = tmp_path / "eval.json"
    result = runner.invoke(app, ["eval", str(tiny_run), "--levels", EVAL_LEVEL, "--attempts", "2", "--json", str(out)])
    assert result.exit_code == 0, result.output
    report = json.loads(out.read_text())
    assert report["format"] == "kinetix-eval/1" and report["update"] == 6
    assert 0.0 <= report["suites"]["all"]["solve_rate"] <= 1.0 and report["levels"][0]["level"] == EVAL_LEVEL


def test_eval_scores_the_reference_levels_converting_on_load(tmp_path, tiny_run):
    """`kinetix eval --levels` takes a folder of reference-format levels (the paper's hold-out suite) as it is."""
    suite = REFERENCE_LEVELS / "s"
    if not suite.is_dir():
        pytest.fail(f"{suite} is missing: run `make reference-levels` (make test does)")
    out = tmp_path / "eval.json"
    result = runner.invoke(app, ["eval", str(tiny_run), "--levels", str(suite), "--attempts", "2", "--json", str(out)])
    assert result.exit_code == 0, result.output
    report = json.loads(out.read_text())
    assert len(report["levels"]) == 10 and report["suites"][str(suite)]["levels"] == 10


def test_finetune_keeps_the_agents_environment_and_evaluates_on_its_levels(tmp_path, tiny_run):
    """--from RUN takes the run's model, observation, action type and frame skip (the tiny run's 4, where
    cpu-small.yaml says 2), unless a --set says otherwise; it evaluates on its own levels."""
    tuned = tmp_path / "tuned"
    sets = [value for value in TINY if not value.startswith(("env.frame_skip", "run.eval_levels"))]
    args = ["finetune", *TRAIN_LEVELS, "--from", str(tiny_run), "--run-dir", str(tuned)]
    result = runner.invoke(app, [*args, "--config", "experiments/cpu-small.yaml", *set_args(sets)])
    assert result.exit_code == 0, result.output
    assert (tuned / "checkpoints" / "6").is_dir()
    config = load_config(tuned / "config.yaml")
    assert config.env.frame_skip == 4 and config.model == load_config(tiny_run / "config.yaml").model
    assert config.run.eval_levels == tuple(TRAIN_LEVELS)


def test_rollout_of_a_trained_policy_runs_in_the_runs_environment(tmp_path, tiny_run):
    """FALL takes the same simulated time whatever the agent does: the tiny run acts every 4 engine steps, the
    open-loop policies at the default 2, so the run's episode has about half the steps."""
    level = tmp_path / "fall.json"
    level.write_text(json.dumps(FALL))
    gif = tmp_path / "run.gif"
    result = runner.invoke(app, ["rollout", str(level), "--policy", str(tiny_run), "-o", str(gif)])
    assert result.exit_code == 0, result.output
    steps = int(re.search(r"solved after (\d+) steps", result.output).group(1))
    baseline = runner.invoke(app, ["rollout", str(level), "--policy", "noop"])
    assert steps <= 0.6 * int(re.search(r"solved after (\d+) steps", baseline.output).group(1))
    assert gif.read_bytes()[:6] == b"GIF89a"


def test_eval_of_something_that_is_not_a_run(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr("sys.argv", ["kinetix", "eval", str(tmp_path)])
    with pytest.raises(SystemExit) as info:
        main()
    assert info.value.code == 2 and "not a run directory" in capsys.readouterr().err
