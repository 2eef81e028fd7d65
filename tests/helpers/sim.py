"""Test helpers: compiled rollouts are cached per size, so the whole suite compiles each size once."""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np

from engine import Params, State, Static, step

CHUNK = 60
"""Engine steps per compiled rollout call (1 s at dt = 1/60); longer runs loop over chunks."""

WORLD = Static(num_polygons=8, num_circles=2, num_joints=2, num_thrusters=1, max_contacts=16)
"""The size most physics tests use: 4 free polygon slots, 2 circles, 2 joints, 1 thruster."""


@functools.cache
def _compiled_chunk(static: Static, batched: bool):
    def one(params, state, actions):
        def body(s, _):
            s, info = step(static, params, s, actions)
            b = s.bodies
            return s, (b.position, b.angle, b.velocity, b.angular_velocity, info.touching, info.dropped_contacts)

        return jax.lax.scan(body, state, None, length=CHUNK)

    fn = jax.vmap(one, in_axes=(None, 0, 0)) if batched else one
    return jax.jit(fn)


class Trajectory:
    """Per-step arrays of a rollout (leading axis = step): position, angle, velocity, angular_velocity,
    touching, dropped."""

    def __init__(self, parts):
        (self.position, self.angle, self.velocity, self.angular_velocity, self.touching, self.dropped) = (
            np.concatenate([np.asarray(p[i]) for p in parts], axis=0) for i in range(6)
        )


def simulate(static: Static, state: State, seconds: float, actions=None, params: Params | None = None):
    """Step one scene for `seconds` (whole chunks). Returns (final state, Trajectory)."""
    params = params or Params()
    actions = jnp.zeros(static.num_actions) if actions is None else jnp.asarray(actions, jnp.float32)
    fn = _compiled_chunk(static, False)
    parts = []
    for _ in range(max(1, round(seconds * 60 / CHUNK))):
        state, part = fn(params, state, actions)
        parts.append(part)
    return state, Trajectory(parts)


def simulate_batch(static: Static, states: State, chunks: int, actions, params: Params | None = None):
    """Step a batch of scenes for `chunks` chunks. Returns (final states, list of per-chunk outputs)."""
    params = params or Params()
    fn = _compiled_chunk(static, True)
    parts = []
    for _ in range(chunks):
        states, part = fn(params, states, actions)
        parts.append(part)
    return states, parts
