"""A level on the device: the engine scene plus the action bindings of its motors and thrusters.

Levels of one size have identical shapes, so a batch of them is the same tree with a leading axis and
switching levels never recompiles.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from flax import struct

from engine import State


@struct.dataclass
class Bindings:
    """Which agent action drives each motor and thruster.

    Attributes:
        motor: (J,) int32 motor binding in 0..3 (ignored for auto motors and joints without a motor).
        motor_auto: (J,) bool; an auto motor always runs at action +1.
        thruster: (T,) int32 thruster binding in 0..1.
    """

    motor: jax.Array
    motor_auto: jax.Array
    thruster: jax.Array


@struct.dataclass
class Level:
    """A task: the initial engine state and its bindings.

    Attributes:
        physics: initial engine `State` (roles ride in `physics.bodies.role`).
        bindings: see `Bindings`.
    """

    physics: State
    bindings: Bindings


def stack_levels(levels: list[Level]) -> Level:
    """Stack levels of one size into a batch (leading axis) of device arrays."""
    return jax.tree.map(lambda *xs: jnp.asarray(np.stack([np.asarray(x) for x in xs])), *levels)


def to_device(level: Level) -> Level:
    """Turn numpy leaves into device arrays."""
    return jax.tree.map(jnp.asarray, level)
