"""Pytest configuration. Helpers live in tests/helpers (on the path): sim.py shares compiled engine rollouts,
runs.py the tiny training runs, whose pool and finished run directories are session fixtures here."""

from __future__ import annotations

import pytest

from helpers.runs import sfl_config, tiny_config
from kinetix_cli.rl.pool import level_pool
from kinetix_cli.rl.train import train


@pytest.fixture(scope="session")
def tiny_pool():
    """The tiny run's training levels on the device."""
    return level_pool(tiny_config())


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory, tiny_pool):
    """A finished tiny run (6 updates, checkpoints 2, 4 and 6, evaluations at 4 and 6): its run directory."""
    run_dir = tmp_path_factory.mktemp("runs") / "tiny"
    train(tiny_config(), run_dir, pool=tiny_pool)
    return run_dir


@pytest.fixture(scope="session")
def sfl_run(tmp_path_factory):
    """The finished tiny SFL run on `LEARN_LEVEL` (300 updates, checkpoints 100, 200, 300): its `TrainResult` and
    run directory."""
    config = sfl_config()
    run_dir = tmp_path_factory.mktemp("runs") / "sfl"
    return train(config, run_dir, pool=level_pool(config)), run_dir
