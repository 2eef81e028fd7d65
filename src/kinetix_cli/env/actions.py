"""Action spaces of the environment and their mapping onto engine actions.

The agent acts per *binding*: 4 motor bindings and 2 thruster bindings at every size. Every joint and
thruster of a level carries a binding (see `kinetix_cli.env.level.Bindings`); all actuators on one binding move
together.

Encodings (ours; the reference's docs and code disagree on the multi-discrete order):
- ``multi-discrete`` (default): int32 (6,) = 4 motor entries in {0: off, 1: forward (+1), 2: backward (-1)}
  then 2 thruster entries in {0: off, 1: on}.
- ``discrete``: int32 () in [0, 11): 0 is no-op; 1..8 drive motor binding (a - 1) // 2 forward when a is odd,
  backward when even; 9 and 10 fire thruster binding 0 and 1. One actuator at a time.
- ``continuous``: float32 (6,) = 4 motor values in [-1, 1] then 2 thruster values in [0, 1] (clipped).

A motor's target speed is action x motor_speed x 6 rad/s; "auto" motors always run at +1 and joints without
a motor ignore actions.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from kinetix_cli.constants import ACTION_TYPES, NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS
from kinetix_cli.env.level import Bindings


@dataclasses.dataclass(frozen=True)
class ActionSpace:
    """Shape and range of one action type.

    Attributes:
        kind: one of `ACTION_TYPES`.
        shape: shape of one action.
        nvec: choices per entry (multi-discrete), the number of choices (discrete), or () (continuous).
        low, high: per-entry bounds of continuous actions.
    """

    kind: str
    shape: tuple[int, ...]
    nvec: tuple[int, ...]
    low: tuple[float, ...] = ()
    high: tuple[float, ...] = ()


def action_space(kind: str) -> ActionSpace:
    """The `ActionSpace` of an action type; raises ValueError naming the choices."""
    m, t = NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS
    if kind == "multi-discrete":
        return ActionSpace(kind, (m + t,), (3,) * m + (2,) * t)
    if kind == "discrete":
        return ActionSpace(kind, (), (2 * m + t + 1,))
    if kind == "continuous":
        return ActionSpace(kind, (m + t,), (), (-1.0,) * m + (0.0,) * t, (1.0,) * (m + t))
    raise ValueError(f"unknown action type {kind!r}; choose one of {', '.join(ACTION_TYPES)}")


def discrete_choice_bindings() -> tuple[int, ...]:
    """The binding (0-5: motors then thrusters) each ``discrete`` choice drives, -1 for the no-op (choice 0)."""
    m, t = NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS
    return (-1, *(c // 2 for c in range(2 * m)), *range(m, m + t))


def binding_values(kind: str, action: jax.Array) -> jax.Array:
    """(6,) float32: motor binding values in [-1, 1] then thruster binding values in [0, 1]."""
    m, t = NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS
    if kind == "multi-discrete":
        action = jnp.asarray(action, jnp.int32)
        motors = jnp.select([action[:m] == 1, action[:m] == 2], [1.0, -1.0], 0.0)
        return jnp.concatenate([motors, (action[m:] == 1).astype(jnp.float32)])
    if kind == "discrete":
        a = jnp.asarray(action, jnp.int32)
        motor = jnp.arange(m)
        motors = jnp.where((a >= 1) & (a <= 2 * m) & ((a - 1) // 2 == motor), jnp.where(a % 2 == 1, 1.0, -1.0), 0.0)
        thrusters = (a == 2 * m + 1 + jnp.arange(t)).astype(jnp.float32)
        return jnp.concatenate([motors, thrusters])
    if kind == "continuous":
        action = jnp.asarray(action, jnp.float32)
        return jnp.concatenate([jnp.clip(action[:m], -1.0, 1.0), jnp.clip(action[m:], 0.0, 1.0)])
    raise ValueError(f"unknown action type {kind!r}")


def engine_actions(bindings: Bindings, values: jax.Array) -> jax.Array:
    """(J + T,) engine actions from (6,) binding values: each joint and thruster reads its binding."""
    motors = jnp.where(bindings.motor_auto, 1.0, values[bindings.motor])
    thrusters = values[NUM_MOTOR_BINDINGS + bindings.thruster]
    return jnp.concatenate([motors, thrusters])


def sample_action(kind: str, key: jax.Array) -> jax.Array:
    """A uniformly random action of type `kind` (the "random" policy)."""
    space = action_space(kind)
    if kind == "multi-discrete":
        return jax.random.randint(key, space.shape, 0, jnp.asarray(space.nvec), jnp.int32)
    if kind == "discrete":
        return jax.random.randint(key, (), 0, space.nvec[0], jnp.int32)
    return jax.random.uniform(key, space.shape, minval=jnp.asarray(space.low), maxval=jnp.asarray(space.high))


def noop_action(kind: str) -> jax.Array:
    """The action that drives nothing (auto motors still run)."""
    space = action_space(kind)
    return jnp.zeros(space.shape, jnp.float32 if kind == "continuous" else jnp.int32)
