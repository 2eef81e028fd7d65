"""Levels on the fly: a fresh batch is valid, reproducible from its key, new for every key, and compiles once."""

from __future__ import annotations

import functools

import chex
import jax
import numpy as np

from engine import SIZES
from kinetix_cli.env.level import level_count
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.generator.sampler import is_valid

COUNT = 16
FRESH = FreshLevels.for_size(SIZES["s"], "s")


@chex.assert_max_traces(n=1)
def _draw(key):
    return FRESH(key, COUNT)


draw = jax.jit(_draw)


def test_fresh_levels_are_valid_reproducible_and_new_for_every_key():
    first, again, other = (jax.device_get(draw(jax.random.key(k))) for k in (1, 1, 2))
    assert level_count(first) == COUNT
    assert jax.jit(jax.vmap(functools.partial(is_valid, FRESH.static)))(first).all()
    jax.tree.map(np.testing.assert_array_equal, first, again)
    positions = first.physics.bodies.position
    assert not np.array_equal(positions, other.physics.bodies.position)
    assert len({row.tobytes() for row in positions}) == COUNT, "every level of a batch differs"


def test_two_draws_of_one_count_in_a_traced_computation_trace_the_sampler_once(monkeypatch):
    # SFL's update and its scoring each draw the same count: the sampler is traced once (fresh_levels is jitted)
    from kinetix_cli.generator import fresh

    traced = []
    sample = fresh.sample_level
    monkeypatch.setattr(fresh, "sample_level", lambda *args: traced.append(1) or sample(*args))
    source = FreshLevels.for_size(SIZES["s"], "s")
    count = 5  # a count no other test draws, so no earlier trace is reused
    jax.make_jaxpr(lambda a, b: (source(a, count), source(b, count)))(jax.random.key(0), jax.random.key(1))
    assert len(traced) == 1
