"""Pytest configuration. Helpers live in tests/helpers (on the path): sim.py shares compiled engine rollouts,
runs.py the tiny training run, whose pool and finished run directory are session fixtures here."""

from __future__ import annotations

import pytest

from helpers.runs import tiny_config
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
