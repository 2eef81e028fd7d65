"""One engine step, as a recipe of named phases.

    gravity -> motors -> thrusters -> collide -> prepare contacts and joints -> warm start
    -> solve velocities (Gauss-Seidel) -> store impulses -> integrate positions -> correct joint drift -> clip

`step(static, params, state, actions)` is pure and jitted with `static` static; vmap it over scenes. Inside other
jitted programs (an environment step, an episode, a training update, curriculum scoring) it is one nested call, so
its trace is made once per `Static` and shared by all of them instead of being traced again for each; XLA inlines
it, so what is computed is unchanged. Each phase runs under a `jax.named_scope` of its name, so profiles (and HLO
dumps) name the phases.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
from flax import struct

from engine.actuators import apply_gravity, apply_motors, apply_thrusters
from engine.config import Params, Static
from engine.contacts import prepare_contacts, store_contact_impulses, warm_start_contacts
from engine.geometry import mass_properties
from engine.joints import correct_joint_positions, prepare_joints, warm_start_joints
from engine.narrowphase import collide, speculative_margins
from engine.pairs import collidable_pairs, pair_table
from engine.solver import solve_velocities, stack_values
from engine.state import Bodies, State


@struct.dataclass
class StepInfo:
    """What happened in a step, for the environment and for diagnostics.

    Attributes:
        touching: (num_pairs,) bool, pair p of `pairs.pair_table(static)` is within `Params.touch_distance`
            at the start of the step (pairs that may not collide never touch).
        dropped_contacts: () int32 contact points that touched but did not fit in `Static.max_contacts`.
    """

    touching: jax.Array
    dropped_contacts: jax.Array


def pack_velocities(bodies: Bodies) -> jax.Array:
    """(N, 3) rows (vx, vy, omega)."""
    return jnp.concatenate([bodies.velocity, bodies.angular_velocity[:, None]], axis=-1)


def integrate_positions(params: Params, bodies: Bodies, v3: jax.Array, inv_mass: jax.Array, inv_inertia):
    """Symplectic Euler: store the solved velocities and move positions [m] and angles [rad] by v dt."""
    moving = (inv_mass > 0) | (inv_inertia > 0)
    v3 = jnp.where(moving[:, None], v3, 0.0)
    return bodies.replace(
        velocity=v3[:, :2],
        angular_velocity=v3[:, 2],
        position=bodies.position + params.dt * v3[:, :2],
        angle=bodies.angle + params.dt * v3[:, 2],
    )


def clip_state(params: Params, bodies: Bodies) -> Bodies:
    """Clip positions, velocities and angular velocities to the reference's bounds."""
    return bodies.replace(
        position=jnp.clip(bodies.position, -params.clip_position, params.clip_position),
        velocity=jnp.clip(bodies.velocity, -params.clip_velocity, params.clip_velocity),
        angular_velocity=jnp.clip(bodies.angular_velocity, -params.clip_angular_velocity, params.clip_angular_velocity),
    )


@functools.partial(jax.jit, static_argnums=(0,))
def step(static: Static, params: Params, state: State, actions: jax.Array) -> tuple[State, StepInfo]:
    """Advance one scene by `params.dt`.

    Args:
        static: capacities (hashable; static under jit).
        params: physical constants.
        state: the scene.
        actions: (J + T,) motor actions in [-1, 1] for each joint, then thruster actions in [0, 1].
    """
    bodies = state.bodies
    with jax.named_scope("mass_properties"):
        inv_mass, inv_inertia = mass_properties(bodies, static.num_polygons)
        inv_mass3 = jnp.stack([inv_mass, inv_mass, inv_inertia], axis=-1)
        v3 = pack_velocities(bodies)

    with jax.named_scope("gravity"):
        v3 = apply_gravity(params, state, inv_mass, v3)
    with jax.named_scope("motors"):
        v3 = apply_motors(static, params, state, actions[: static.num_joints], inv_inertia, v3)
    with jax.named_scope("thrusters"):
        v3 = apply_thrusters(static, params, state, actions[static.num_joints :], inv_mass, inv_inertia, v3)

    with jax.named_scope("collide"):
        margins = speculative_margins(static, bodies, v3, params.speculative_distance, params.dt)
        manifold = collide(static, bodies, margins)
        table = pair_table(static)
        collidable = collidable_pairs(static, bodies, state.joints)[table.point_pair]
        body_movable = inv_mass3.sum(-1) > 0
        movable = body_movable[table.a[table.point_pair]] | body_movable[table.b[table.point_pair]]
    with jax.named_scope("prepare_contacts"):
        contacts, dropped = prepare_contacts(
            static, params, bodies, inv_mass3, v3, manifold, manifold.valid & collidable & movable, state.contacts
        )
    with jax.named_scope("prepare_joints"):
        joints = prepare_joints(static, params, bodies, state.joints, inv_mass, inv_inertia)

    with jax.named_scope("warm_start"):
        v3 = warm_start_joints(joints, v3)
        v3 = warm_start_contacts(contacts, v3)
    with jax.named_scope("solve_velocities"):
        v3, impulses = solve_velocities(static, contacts, joints, v3)

    with jax.named_scope("store_impulses"):
        cache = store_contact_impulses(
            static,
            contacts,
            manifold,
            stack_values(impulses.contact_normal, contacts.normal_impulse),
            stack_values(impulses.contact_tangent, contacts.tangent_impulse),
        )
        new_joints = state.joints.replace(
            impulse=stack_values(impulses.joint_point, joints.impulse),
            angular_impulse=stack_values(impulses.joint_angle, joints.angular_impulse),
            lower_impulse=stack_values(impulses.joint_lower, joints.lower_impulse),
            upper_impulse=stack_values(impulses.joint_upper, joints.upper_impulse),
        )

    with jax.named_scope("integrate_positions"):
        bodies = integrate_positions(params, bodies, v3, inv_mass, inv_inertia)
    with jax.named_scope("correct_joint_positions"):
        bodies = correct_joint_positions(static, params, bodies, new_joints, inv_mass, inv_inertia)
    with jax.named_scope("clip"):
        bodies = clip_state(params, bodies)

    with jax.named_scope("touching"):
        touch_points = manifold.valid & collidable & (manifold.separation <= params.touch_distance)
        touching = jnp.zeros(table.num_pairs, bool).at[jnp.asarray(table.point_pair)].max(touch_points)
    new_state = state.replace(bodies=bodies, joints=new_joints, contacts=cache)
    return new_state, StepInfo(touching=touching, dropped_contacts=dropped)


@functools.partial(jax.jit, static_argnums=(0,))
def step_batch(static: Static, params: Params, states: State, actions: jax.Array) -> tuple[State, StepInfo]:
    """`step` vmapped over a leading batch axis of `states` and `actions` (params shared)."""
    return jax.vmap(step, in_axes=(None, None, 0, 0))(static, params, states, actions)


def touching_matrix(static: Static, touching: jax.Array) -> jax.Array:
    """(N, N) symmetric bool from the per-pair `StepInfo.touching` (num_pairs,)."""
    table = pair_table(static)
    a, b = jnp.asarray(table.a), jnp.asarray(table.b)
    n = static.num_bodies
    matrix = jnp.zeros((n, n), bool).at[a, b].set(touching)
    return matrix | matrix.T
