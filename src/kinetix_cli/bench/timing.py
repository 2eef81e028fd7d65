"""Timing shared by the benchmarks: compile time apart from steady state, the median rate over repeated calls,
and the versioned JSON record of a benchmark (machine, versions, config, results)."""

from __future__ import annotations

import dataclasses
import statistics
import time
from collections.abc import Callable

import jax

from kinetix_cli.provenance import environment_info


def time_calls(
    fn: Callable, carry: tuple, steps_per_call: int, min_time: float, statistic: Callable = statistics.median
) -> tuple[float, float, int]:
    """Compile `fn(*carry) -> carry` and call it repeatedly for at least `min_time` seconds (after a warm-up
    call). Returns (compile seconds, steps/s by `statistic` over the calls (the median; `max` for a limit), timed
    calls)."""
    start = time.perf_counter()
    compiled = jax.jit(fn).lower(*carry).compile()
    compile_s = time.perf_counter() - start
    carry = jax.block_until_ready(compiled(*carry))
    rates, spent = [], 0.0
    while len(rates) < 2 or spent < min_time:
        start = time.perf_counter()
        carry = jax.block_until_ready(compiled(*carry))
        elapsed = time.perf_counter() - start
        spent += elapsed
        rates.append(steps_per_call / elapsed)
    return compile_s, statistic(rates), len(rates)


def time_keyed(step_fn: Callable, carry, keys, steps: int, min_time: float) -> tuple[float, float, int]:
    """Time `scan(vmap(step_fn(carry, key)))` with a fresh random key per scene and step; `carry` is batched."""

    def rollout(carry, keys):
        def body(both, _):
            carry, keys = both
            split = jax.vmap(jax.random.split)(keys)
            return (jax.vmap(step_fn)(carry, split[:, 0]), split[:, 1]), None

        return jax.lax.scan(body, (carry, keys), None, length=steps)[0]

    return time_calls(rollout, (carry, keys), keys.shape[0] * steps, min_time)


def bench_record(config, results) -> dict:
    """The payload of a benchmark's `kinetix-bench/1` file: machine, versions, its config and its results."""
    return {
        **environment_info(),
        "config": dataclasses.asdict(config),
        "results": [dataclasses.asdict(r) for r in results],
    }
