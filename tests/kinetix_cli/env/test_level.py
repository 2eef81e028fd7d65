"""Levels on the device: `to_device` and `stack_levels` give JAX arrays with JAX's dtypes and the same values, and
compile nothing (on jax 0.10 `jnp.asarray` of a numpy array compiles a small program per new shape)."""

from __future__ import annotations

import jax
import numpy as np

from engine import SIZES
from helpers.levels import CAR, FALL
from kinetix_cli.env.level import stack_levels, to_device
from kinetix_cli.levels.parse import parse_level

COMPILE_EVENT = "/jax/core/compile/backend_compile_duration"


def test_levels_go_to_the_device_with_jaxs_dtypes_and_their_values_and_compile_nothing():
    built = [parse_level(spec, "test.json").build(SIZES["s"]) for spec in (CAR, FALL) * 4]  # shapes of (7, ...)
    wide = jax.tree.map(
        lambda *xs: np.stack(xs).astype(np.float64 if xs[0].dtype.kind == "f" else xs[0].dtype), *built[:7]
    )
    compiled = []

    def listen(event, duration, **_):
        if event == COMPILE_EVENT:
            compiled.append(event)

    jax.monitoring.register_event_duration_secs_listener(listen)
    try:
        on_device, batch = to_device(wide), stack_levels(built[:7])
    finally:
        jax.monitoring.unregister_event_duration_listener(listen)
    assert compiled == []
    for host, device in zip(jax.tree.leaves(wide), jax.tree.leaves(on_device), strict=True):
        assert isinstance(device, jax.Array) and device.dtype == jax.numpy.asarray(host).dtype  # float64 -> float32
        np.testing.assert_array_equal(np.asarray(device), host.astype(device.dtype))
    for leaf, *levels in zip(*(jax.tree.leaves(t) for t in (batch, *built[:7])), strict=True):
        assert isinstance(leaf, jax.Array) and leaf.shape == (7, *np.shape(levels[0]))
        np.testing.assert_array_equal(np.asarray(leaf), np.stack(levels))
