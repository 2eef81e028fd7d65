"""Training runs on disk: metrics and checkpoints are written, and a resumed run ends where an uninterrupted one
does, bit for bit."""

from __future__ import annotations

import json
from pathlib import Path

import jax
import numpy as np
import pytest

from kinetix_cli.config import load_config
from kinetix_cli.errors import UserError
from kinetix_cli.train import level_pool, train

TINY = [
    "levels.source=files",
    "levels.files=[levels/s/rocket-car-jump.json, levels/s/pad-to-pad.json]",
    "model.width=16",
    "model.actor_critic_layers=1",
    "ppo.num_envs=8",
    "ppo.num_steps=8",
    "ppo.num_minibatches=2",
    "ppo.update_epochs=1",
    "ppo.total_timesteps=384",  # 6 updates
    "run.checkpoint_every=2",
    "run.eval_every=0",  # no evaluation during training (each evaluator is one more compile), except in EVAL
]
# Evaluation during training at update 4 and after the last (6), on one level.
EVAL = ["run.eval_every=4", "run.eval_levels=[levels/s/rocket-car-jump.json]", "run.eval_attempts=3"]


@pytest.fixture(scope="module")
def tiny():
    config = load_config("experiments/cpu-small.yaml", TINY)
    return config, level_pool(config)


class Crash(Exception):
    pass


def test_resume_after_a_crash_matches_an_uninterrupted_run(tmp_path, tiny):
    _, pool = tiny
    config = load_config("experiments/cpu-small.yaml", [*TINY, *EVAL])
    whole = train(config, tmp_path / "whole", pool=pool)

    def crash_after_3(record):
        if record["update"] == 3:
            raise Crash

    with pytest.raises(Crash):
        train(config, tmp_path / "cut", pool=pool, progress=crash_after_3)
    assert sorted(p.name for p in (tmp_path / "cut" / "checkpoints").iterdir()) == ["2"]
    resumed = train(config, tmp_path / "cut", resume=True, pool=pool)

    jax.tree.map(np.testing.assert_array_equal, whole.params, resumed.params)
    lines = [json.loads(x) for x in (tmp_path / "cut" / "metrics.jsonl").read_text().splitlines()]
    assert [x["update"] for x in lines] == [1, 2, 3, 4, 5, 6]
    assert {"steps", "sps", "return", "solve_rate", "policy_loss", "value_loss", "entropy"} <= set(lines[0])
    uncut = [json.loads(x) for x in (tmp_path / "whole" / "metrics.jsonl").read_text().splitlines()]
    evaluated = [(x["update"], x["eval_solve_rate"], x["eval_return"]) for x in lines if "eval_solve_rate" in x]
    assert [e[0] for e in evaluated] == [4, 6]
    assert evaluated == [(x["update"], x["eval_solve_rate"], x["eval_return"]) for x in uncut if "eval_return" in x]


def test_evaluation_during_training_is_kinetix_eval_of_the_parameters(tmp_path, tiny):
    from kinetix_cli.evaluate import evaluate

    _, pool = tiny
    config = load_config("experiments/cpu-small.yaml", [*TINY, *EVAL])
    runner = train(config, tmp_path / "run", pool=pool)
    last = json.loads((tmp_path / "run" / "metrics.jsonl").read_text().splitlines()[-1])
    (result,) = evaluate(config, runner.params, ["levels/s/rocket-car-jump.json"], 3, seed=config.run.seed)
    assert last["eval_solve_rate"] == result.solve_rate and last["eval_return"] == result.mean_return


def test_missing_evaluation_levels_fail_before_training(tmp_path, tiny):
    config = load_config("experiments/cpu-small.yaml", [*TINY, *EVAL, "run.eval_levels=[levels/nowhere]"])
    with pytest.raises(UserError, match="levels/nowhere: no such file"):
        train(config, tmp_path / "run", pool=tiny[1])
    assert not (tmp_path / "run" / "metrics.jsonl").exists()


def test_refuses_to_overwrite_a_run(tmp_path, tiny):
    config, pool = tiny
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "notes.txt").write_text("mine")
    with pytest.raises(UserError, match="not empty"):
        train(config, tmp_path / "run", pool=pool)


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory, tiny):
    config, pool = tiny
    run_dir = tmp_path_factory.mktemp("runs") / "tiny"
    train(config, run_dir, pool=pool)
    return run_dir


def test_eval_finetune_and_rollout_from_a_run(tmp_path, tiny_run):
    from typer.testing import CliRunner

    from kinetix_cli.cli import app

    runner = CliRunner()
    out = tmp_path / "eval.json"
    level = "levels/s/rocket-car-jump.json"
    result = runner.invoke(app, ["eval", str(tiny_run), "--levels", level, "--attempts", "2", "--json", str(out)])
    assert result.exit_code == 0, result.output
    report = json.loads(out.read_text())
    assert report["format"] == "kinetix-eval/1" and report["update"] == 6
    assert 0.0 <= report["suites"]["all"]["solve_rate"] <= 1.0 and report["levels"][0]["level"] == level

    sets = [arg for pair in (("--set", x) for x in TINY[2:]) for arg in pair]
    tuned = tmp_path / "tuned"
    args = [
        "finetune",
        level,
        "--from",
        str(tiny_run),
        "--run-dir",
        str(tuned),
        "--config",
        "experiments/cpu-small.yaml",
    ]
    result = runner.invoke(app, [*args, *sets])
    assert result.exit_code == 0, result.output
    assert (tuned / "checkpoints" / "6").is_dir()
    assert load_config(tuned / "config.yaml").run.eval_levels == (level,)  # finetune evaluates on its own levels

    gif = tmp_path / "run.gif"
    result = runner.invoke(app, ["rollout", level, "--policy", str(tiny_run), "-o", str(gif)])
    assert result.exit_code == 0 and gif.stat().st_size > 0, result.output


def test_eval_scores_the_reference_levels_converting_on_load(tmp_path, tiny_run):
    """`kinetix eval --levels` takes a folder of reference-format levels (the paper's hold-out suite) as it is."""
    from typer.testing import CliRunner

    from kinetix_cli.cli import app

    suite = Path(__file__).resolve().parents[2] / ".cache" / "reference-levels" / "s"
    if not suite.is_dir():
        pytest.fail(f"{suite} is missing: run `make reference-levels` (make test does)")
    out = tmp_path / "eval.json"
    result = CliRunner().invoke(
        app, ["eval", str(tiny_run), "--levels", str(suite), "--attempts", "2", "--json", str(out)]
    )
    assert result.exit_code == 0, result.output
    report = json.loads(out.read_text())
    assert len(report["levels"]) == 10 and report["suites"][str(suite)]["levels"] == 10


def test_eval_of_something_that_is_not_a_run(tmp_path, monkeypatch, capsys):
    from kinetix_cli.cli import main

    monkeypatch.setattr("sys.argv", ["kinetix", "eval", str(tmp_path)])
    with pytest.raises(SystemExit) as info:
        main()
    assert info.value.code == 2 and "not a run directory" in capsys.readouterr().err


@pytest.mark.slow
def test_wandb_offline_logs_next_to_the_run(tmp_path, tiny):
    config, pool = tiny
    import dataclasses

    config = dataclasses.replace(config, run=dataclasses.replace(config.run, wandb="offline"))
    train(config, tmp_path / "run", pool=pool)
    assert list((tmp_path / "run" / "wandb").glob("offline-run-*"))


def test_init_from_loads_the_checkpoint_parameters(tmp_path, tiny_run, tiny):
    from kinetix_cli.evaluate import load_policy

    _, pool = tiny
    wider = load_config("experiments/cpu-small.yaml", [*TINY, "model.width=32", f"run.init_from={tiny_run}"])
    with pytest.raises(UserError, match="does not match"):  # the checkpoint was read and compared
        train(wider, tmp_path / "wider", pool=pool)

    def distance(a, b):
        return max(float(np.abs(x - y).max()) for x, y in zip(jax.tree.leaves(a), jax.tree.leaves(b), strict=True))

    one_update = [*TINY, "ppo.total_timesteps=64"]
    loaded = load_policy(tiny_run)[1]
    tuned = train(
        load_config("experiments/cpu-small.yaml", [*one_update, f"run.init_from={tiny_run}"]), tmp_path / "a", pool=pool
    )
    fresh = train(load_config("experiments/cpu-small.yaml", [*one_update, "run.seed=1"]), tmp_path / "b", pool=pool)
    # one Adam update moves each weight by about lr = 3e-4; another seed's initialisation is far away
    assert distance(tuned.params, loaded) < 0.01 < distance(fresh.params, loaded)
