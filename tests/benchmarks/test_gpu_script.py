"""benchmarks/gpu.sh at CPU sizes (TINY=1): every step runs and its summary reads the files the steps wrote."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from helpers.paths import REPO

pytestmark = pytest.mark.slow


def run_script(out: Path, **settings: str) -> subprocess.CompletedProcess:
    bin_dir = Path(sys.executable).parent
    env = dict(os.environ, TINY="1", KINETIX=str(bin_dir / "kinetix"), PYTHON=sys.executable, **settings)
    done = subprocess.run(
        [REPO / "benchmarks" / "gpu.sh", out], cwd=REPO, env=env, capture_output=True, text=True, timeout=1200
    )
    assert done.returncode == 0, done.stderr[-3000:]
    engine = json.loads((out / "engine-m.json").read_text())
    assert {r["engine"] for r in engine["results"]} == {"kinetix", "jax2d"}
    train = json.loads((out / "train-m.json").read_text())
    assert [r["model"] for r in train["results"]] == ["pi-mlp", "transformer"]
    paper = json.loads((out / "train-m-paper.json").read_text())
    assert [(r["model"], r["envs"]) for r in paper["results"]] == [("transformer", 16)]
    assert all(r["steps_per_s"] > 0 for r in engine["results"] + train["results"] + paper["results"])
    for heading in ("| engine, size m |", "| model | envs |", "| at the paper's sizes, m |"):
        assert heading in done.stdout
    return done


def test_gpu_script_runs_at_tiny_sizes(tmp_path):
    done = run_script(tmp_path, EVAL_LEVELS="levels/s")
    evaluation = json.loads((tmp_path / "sfl" / "eval.json").read_text())
    assert evaluation["attempts"] == 2 and evaluation["suites"]["levels/s"]["levels"] > 0
    assert "| SFL, transformer, size s |" in done.stdout


def test_gpu_script_leaves_sfl_out_at_zero_seconds(tmp_path):
    done = run_script(tmp_path, SFL_SECONDS="0")
    assert not (tmp_path / "sfl").exists()
    assert "| SFL, transformer, size s |" not in done.stdout
