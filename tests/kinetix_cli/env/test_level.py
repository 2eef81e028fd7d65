"""Levels on the device: `to_device` and `stack_levels` give JAX arrays with JAX's dtypes and the same values."""

from __future__ import annotations

import jax
import numpy as np

from engine import SIZES
from helpers.levels import CAR, FALL
from kinetix_cli.env.level import stack_levels, to_device
from kinetix_cli.levels.parse import parse_level


def test_levels_go_to_the_device_with_jaxs_dtypes_and_their_values():
    built = [parse_level(spec, "test.json").build(SIZES["s"]) for spec in (CAR, FALL)]
    wide = jax.tree.map(lambda x: np.asarray(x, np.float64 if np.asarray(x).dtype.kind == "f" else None), built[0])
    on_device = to_device(wide)
    for host, device in zip(jax.tree.leaves(wide), jax.tree.leaves(on_device), strict=True):
        assert isinstance(device, jax.Array) and device.dtype == jax.numpy.asarray(host).dtype  # float64 -> float32
        np.testing.assert_array_equal(np.asarray(device), host.astype(device.dtype))
    batch = stack_levels(built)
    for leaf, first, second in zip(*(jax.tree.leaves(t) for t in (batch, *built)), strict=True):
        assert isinstance(leaf, jax.Array) and leaf.shape == (2, *np.shape(first))
        np.testing.assert_array_equal(np.asarray(leaf), np.stack([first, second]))
