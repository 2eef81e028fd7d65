"""`bench.timing.time_calls`: the rate of calls timed by a clock, as their median or, for a limit, the fastest."""

from __future__ import annotations

import itertools
from types import SimpleNamespace

import jax.numpy as jnp

from kinetix_cli.bench import timing


def test_time_calls_gives_the_median_or_the_statistic_asked_for(monkeypatch):
    def timed(**options):
        # the clock: compile from 0 to 0, then calls of 1.0, 0.5 and 3.0 s (10 steps each: 10, 20, 3.3 steps/s)
        clock = itertools.chain([0.0, 0.0], [0.0, 1.0, 1.0, 1.5, 1.5, 4.5])
        monkeypatch.setattr(timing, "time", SimpleNamespace(perf_counter=lambda: next(clock)))
        return timing.time_calls(lambda x: (x + 1,), (jnp.zeros(()),), 10, min_time=4.5, **options)

    _, median, calls = timed()
    assert calls == 3 and abs(median - 10.0) < 1e-9  # [steps/s]
    _, fastest, _ = timed(statistic=max)
    assert abs(fastest - 20.0) < 1e-9  # [steps/s]
