"""benchmarks/ablation.sh at a tiny budget: each variant's settings reach its run, every seed is evaluated, and the
summary table lists every variant."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from helpers.paths import REPO

pytestmark = pytest.mark.slow


def test_ablation_script_runs_its_variants(tmp_path):
    bin_dir = Path(sys.executable).parent
    variants = "today:16384:;mask:16384:model.mask_unused_actions=true,env.dense_reward_scale=0.2"
    env = dict(
        os.environ,
        KINETIX=str(bin_dir / "kinetix"),
        PYTHON=sys.executable,
        VARIANTS=variants,
        SEEDS="0",
        ATTEMPTS="2",
        SUITES="levels/s",
    )
    done = subprocess.run(
        [REPO / "benchmarks" / "ablation.sh", tmp_path], cwd=REPO, env=env, capture_output=True, text=True, timeout=1200
    )
    assert done.returncode == 0, done.stderr[-3000:]
    config = yaml.safe_load((tmp_path / "mask-0" / "config.yaml").read_text())
    assert config["model"]["mask_unused_actions"] is True and config["env"]["dense_reward_scale"] == 0.2
    assert yaml.safe_load((tmp_path / "today-0" / "config.yaml").read_text())["model"]["mask_unused_actions"] is False
    for name in ("today-0", "mask-0"):
        assert json.loads((tmp_path / name / "eval.json").read_text())["attempts"] == 2
        assert int((tmp_path / name / "wall_seconds").read_text()) > 0
    assert "| today | levels/s |" in done.stdout and "| mask | levels/s |" in done.stdout
