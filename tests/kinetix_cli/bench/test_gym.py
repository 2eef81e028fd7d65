"""`kinetix bench gym`: the four ways of stepping side by side at each batch size (fresh levels too, with the cost of
a new batch), and a bad source is a user error."""

from __future__ import annotations

import pytest

from kinetix_cli.bench.gym import GymBenchConfig, bench_gym
from kinetix_cli.errors import UserError


@pytest.mark.slow
def test_gym_bench_reports_each_path():
    results = bench_gym(GymBenchConfig(levels="s", envs=(2,), steps=2, min_time=0.0))
    assert [r.path for r in results] == ["KinetixEnv", "gymnax", "gymnax-per-step", "gymnasium"]
    assert all(r.envs == 2 and r.steps_per_s > 0 and r.calls >= 2 for r in results)


@pytest.mark.slow
def test_gym_bench_runs_on_fresh_levels_and_times_a_new_batch():
    results = bench_gym(GymBenchConfig(levels="fresh", size="s", envs=(2,), steps=2, min_time=0.0))
    assert [r.path for r in results] == ["refresh_levels", "KinetixEnv", "gymnax", "gymnax-per-step", "gymnasium"]
    assert results[0].envs == 1024 and all(r.steps_per_s > 0 for r in results)


def test_gym_bench_rejects_a_missing_source():
    with pytest.raises(UserError, match="no/such: no such file or folder"):
        bench_gym(GymBenchConfig(levels="no/such", envs=(2,)))
