"""Actuators and external forces: gravity, joint motors and thrusters, applied to velocities before the solve."""

from __future__ import annotations

import jax
import jax.numpy as jnp

from engine.config import Params, Static
from engine.geometry import cross, rotate
from engine.joints import joint_usable
from engine.state import State


def apply_gravity(params: Params, state: State, inv_mass: jax.Array, v3: jax.Array) -> jax.Array:
    """v += g dt for every movable body. v3: (N, 3) (vx, vy, omega)."""
    movable = (inv_mass > 0)[:, None]
    return v3.at[:, :2].add(jnp.where(movable, state.gravity * params.dt, 0.0))


def apply_motors(
    static: Static,
    params: Params,
    state: State,
    motor_actions: jax.Array,
    inv_inertia: jax.Array,
    v3: jax.Array,
) -> jax.Array:
    """Drive each motorised revolute joint towards its target relative speed.

    The target is omega_b - omega_a = motor_speed * action * base_motor_speed (action in [-1, 1]). The change
    of relative speed per step is base_motor_power * power * dt * tanh(0.1 |error|), as in the reference, but
    never more than the error itself (the reference overshoots and rings). A motor pushing into a joint
    limit fades out within `motor_limit_fade` of it. motor_actions: (J,). Returns v3 (N, 3).
    """
    if static.num_joints == 0:
        return v3
    j = state.joints
    a, b = j.body_a, j.body_b
    on = joint_usable(j, state.bodies) & j.motor_on & ~j.fixed
    i_a, i_b = inv_inertia[a], inv_inertia[b]
    total = i_a + i_b
    target = j.motor_speed * jnp.clip(motor_actions, -1.0, 1.0) * params.base_motor_speed
    error = v3[b, 2] - v3[a, 2] - target
    reach = params.base_motor_power * j.motor_power * params.dt * jnp.tanh(0.1 * jnp.abs(error))
    change = -jnp.sign(error) * jnp.minimum(jnp.abs(error), reach)

    angle = state.bodies.angle[b] - state.bodies.angle[a]
    fade_up = jnp.clip((j.max_angle - angle) / params.motor_limit_fade, 0.0, 1.0)
    fade_down = jnp.clip((angle - j.min_angle) / params.motor_limit_fade, 0.0, 1.0)
    fade = jnp.where(j.has_limits, jnp.where(change > 0, fade_up, fade_down), 1.0)
    change = jnp.where(on & (total > 0), change * fade, 0.0)

    impulse = change / jnp.where(total > 0, total, 1.0)  # angular impulse on b, minus on a [N m s]
    n = static.num_bodies
    d_omega = jax.nn.one_hot(b, n).T @ (i_b * impulse) - jax.nn.one_hot(a, n).T @ (i_a * impulse)
    return v3.at[:, 2].add(d_omega)


def apply_thrusters(
    static: Static,
    params: Params,
    state: State,
    thruster_actions: jax.Array,
    inv_mass: jax.Array,
    inv_inertia: jax.Array,
    v3: jax.Array,
) -> jax.Array:
    """Push bodies along their thrusters: impulse = base_thruster_power * power * action * dt [N s].

    The impulse acts at the thruster's anchor, so an off-centre thruster also spins its body.
    thruster_actions: (T,) in [0, 1]. Returns v3 (N, 3).
    """
    if static.num_thrusters == 0:
        return v3
    t = state.thrusters
    body = t.body
    on = t.active & state.bodies.active[body]
    angle = state.bodies.angle[body]
    direction = rotate(jnp.stack([jnp.cos(t.angle), jnp.sin(t.angle)], -1), angle)
    magnitude = params.base_thruster_power * t.power * jnp.clip(thruster_actions, 0.0, 1.0) * params.dt
    impulse = direction * jnp.where(on, magnitude, 0.0)[:, None]
    lever = rotate(t.anchor, angle)
    dv = jnp.concatenate(
        [inv_mass[body, None] * impulse, (inv_inertia[body] * cross(lever, impulse))[:, None]], axis=-1
    )
    return v3 + jax.nn.one_hot(body, static.num_bodies).T @ dv
