"""`kinetix bench train`: one result per model and environment count, through the CLI with a JSON file; bad
options are one-line errors."""

from __future__ import annotations

import json

import pytest

from kinetix_cli.bench.train import TrainBenchConfig, bench_train
from kinetix_cli.errors import UserError

TINY = {"envs": (4,), "num_steps": 4, "epochs": 1, "minibatches": 2, "width": 8, "layers": 1, "min_time": 0.0}


@pytest.mark.slow  # a PPO update compile (~20 s): make test-all; the option checks below stay in make test
def test_train_bench_writes_a_row_per_model_number_type_and_device_count(tmp_path):
    from typer.testing import CliRunner

    from kinetix_cli.cli.app import app

    out = tmp_path / "train.json"
    args = ["bench", "train", "--models", "pi-mlp", "--envs", "4", "--steps", "4", "--epochs", "1"]
    args += ["--minibatches", "2", "--width", "8", "--layers", "1", "--min-time", "0", "--json", str(out)]
    args += ["--compute", "float32,bfloat16"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    report = json.loads(out.read_text())
    assert report["format"] == "kinetix-bench/1"
    rows = report["results"]
    expected = [("pi-mlp", "symbolic-entity", 4, "float32", 1), ("pi-mlp", "symbolic-entity", 4, "bfloat16", 1)]
    assert [(r["model"], r["observation"], r["envs"], r["compute"], r["devices"]) for r in rows] == expected
    assert all(r["steps_per_s"] > 0 and r["calls"] >= 2 and r["parameters"] > 0 for r in rows)


@pytest.mark.parametrize(
    ("change", "flag"),
    [
        ({"size": "xl"}, "--size"),
        ({"models": ("cnn",)}, "--models"),
        ({"minibatches": 3}, "--minibatches"),
        ({"computes": ("float16",)}, "--compute"),
    ],
)
def test_train_bench_rejects_bad_options(change, flag):
    with pytest.raises(UserError, match=flag):
        bench_train(TrainBenchConfig(**(TINY | change)))
