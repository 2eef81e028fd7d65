"""`kinetix bench env`: one result per observation and batch size, and bad options are user errors."""

from __future__ import annotations

import pytest

from kinetix_cli.bench.env import EnvBenchConfig, bench_env
from kinetix_cli.errors import UserError


@pytest.mark.slow  # a benchmark's smoke test (13 s); its option checks stay in make test
def test_env_bench_reports_each_observation_and_batch():
    config = EnvBenchConfig(size="s", envs=(2,), observations=("symbolic-flat",), steps=2, min_time=0.0)
    (result,) = bench_env(config)
    assert (result.observation, result.size, result.envs) == ("symbolic-flat", "s", 2)
    assert result.steps_per_s > 0 and result.calls >= 2


@pytest.mark.parametrize(("field", "value"), [("size", "xl"), ("observations", ("rgb",))])
def test_env_bench_rejects_unknown_options(field, value):
    config = EnvBenchConfig(**{field: value, "envs": (2,), "steps": 1, "min_time": 0.0})
    with pytest.raises(UserError):
        bench_env(config)
