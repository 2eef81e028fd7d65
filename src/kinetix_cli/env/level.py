"""A level on the device: the engine scene, the action bindings of its motors and thrusters, and its physical
constants.

Levels of one size have identical shapes, so a batch of them is the same tree with a leading axis and
switching levels never recompiles.
"""

from __future__ import annotations

import jax
import numpy as np
from flax import struct

from engine import Params, State


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
    """A task: the initial engine state, its bindings and the engine constants it runs with.

    Attributes:
        physics: initial engine `State` (roles ride in `physics.bodies.role`, gravity in `physics.gravity`).
        bindings: see `Bindings`.
        engine_params: the engine `Params` of this level (a level file's `params` overrides on top of the
            defaults); every leaf is a scalar, with the batch's leading axis in a batch of levels.
    """

    physics: State
    bindings: Bindings
    engine_params: Params


def default_engine_params() -> Params:
    """`engine.Params()` with float32 numpy leaves, the form every level carries."""
    return jax.tree.map(np.float32, Params())


def make_level(physics: State, bindings: Bindings, engine_params: Params | None = None) -> Level:
    """A level with `engine_params` (default: the engine's defaults) as float32 scalars."""
    params = default_engine_params() if engine_params is None else jax.tree.map(np.float32, engine_params)
    return Level(physics, bindings, params)


def empty_bindings(num_joints: int, num_thrusters: int) -> Bindings:
    """Bindings of a level without motors or thrusters: every slot bound to 0 (numpy leaves)."""
    return Bindings(
        motor=np.zeros(num_joints, np.int32),
        motor_auto=np.zeros(num_joints, bool),
        thruster=np.zeros(num_thrusters, np.int32),
    )


def stack_levels(levels: list[Level]) -> Level:
    """Stack levels of one size into a batch (leading axis) of device arrays."""
    return to_device(jax.tree.map(lambda *xs: np.stack([np.asarray(x) for x in xs]), *levels))


def level_count(levels: Level) -> int:
    """The number of levels in a batch (its leading axis)."""
    return int(levels.bindings.motor.shape[0])


def index_level(levels: Level, index) -> Level:
    """Level `index` of a batch (numpy or device leaves; `index` may be traced)."""
    return jax.tree.map(lambda x: x[index], levels)


def share_engine_params(levels: Level) -> tuple[Level, Level | int]:
    """A batch of levels ready for `jax.vmap`, and its `in_axes`: when every level runs with the same engine
    constants (a host check; generated levels always do), they are kept once, unbatched, so the step sees scalars
    as it does for a single level (faster, and the same floats); otherwise the batch is returned as it is."""
    params = jax.tree.map(np.asarray, levels.engine_params)
    if all(np.all(x == x[0]) for x in jax.tree.leaves(params)):
        shared = levels.replace(engine_params=jax.tree.map(lambda x: x[0], params))
        return shared, Level(physics=0, bindings=0, engine_params=None)
    return levels, 0


def draw_level(levels: Level, key: jax.Array) -> Level:
    """One level drawn uniformly from a batch `levels` (device arrays); jittable, vmappable over keys."""
    return index_level(levels, jax.random.randint(key, (), 0, level_count(levels)))


def draw_levels(levels: Level, key: jax.Array, count: int) -> Level:
    """`count` levels drawn uniformly (with replacement) from a batch `levels`, one key each; jittable."""
    return jax.vmap(draw_level, in_axes=(None, 0))(levels, jax.random.split(key, count))


def to_device(level: Level) -> Level:
    """Turn numpy leaves into device arrays. `jax.device_put`, not `jnp.asarray`: on this jax (0.10) `jnp.asarray`
    of a numpy array outside a trace compiles a small program for every new shape and dtype (~30 ms each here, and a
    level has ~50 arrays); both give the same dtypes (float64 to float32, int64 to int32) and values."""
    return jax.device_put(level)


def to_host(tree):
    """Device tree -> numpy tree (for host-side rendering and files)."""
    return jax.tree.map(np.asarray, tree)
