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


def test_gpu_script_runs_at_tiny_sizes(tmp_path):
    bin_dir = Path(sys.executable).parent
    env = dict(os.environ, TINY="1", KINETIX=str(bin_dir / "kinetix"), PYTHON=sys.executable, EVAL_LEVELS="levels/s")
    done = subprocess.run(
        [REPO / "benchmarks" / "gpu.sh", tmp_path], cwd=REPO, env=env, capture_output=True, text=True, timeout=1200
    )
    assert done.returncode == 0, done.stderr[-3000:]
    engine = json.loads((tmp_path / "engine-m.json").read_text())
    assert {r["engine"] for r in engine["results"]} == {"kinetix", "jax2d"}
    train = json.loads((tmp_path / "train-m.json").read_text())
    assert [r["model"] for r in train["results"]] == ["pi-mlp", "transformer"]
    assert all(r["steps_per_s"] > 0 for r in engine["results"] + train["results"])
    evaluation = json.loads((tmp_path / "sfl" / "eval.json").read_text())
    assert evaluation["attempts"] == 2 and evaluation["suites"]["levels/s"]["levels"] > 0
    for heading in ("| engine, size m |", "| model | envs |", "| SFL, transformer, size s |"):
        assert heading in done.stdout
