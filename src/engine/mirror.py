"""The left-right mirror image of a scene: reflected in the arena's vertical centre line, x -> 5 - x.

The engine's physics has no left or right, so the mirror image of a scene, stepped with mirrored actions (every
motor turning the other way, thrusters as they are: they are mirrored with their bodies), follows the mirror image
of the scene's trajectory. `tests/engine/test_mirror.py` holds the engine to that.

What changes, and how:

- bodies: x of the position and of the velocity negated about the centre line; angle and angular velocity
  negated; polygon vertices (body frame) have x negated and their order reversed, so they stay counter-clockwise
  (a triangle repeats its new first vertex in slot 3). The arena's left and right walls swap slots (1 and 2),
  so slot 1 stays the left wall; joints and thrusters follow their bodies to the new slots.
- joints: body-frame anchors have x negated; a fixed joint's held angle is negated; limits [lo, hi] on
  angle_b - angle_a become [-hi, -lo]. The motor keeps its speed: the caller reverses its action
  (`mirror_motor_actions`).
- thrusters: body-frame anchor x negated, the direction's angle a becomes pi - a.
- gravity: x negated.
- empty (inactive) slots stay as they are.
- the warm-start caches (contact impulses and their feature ids, joint impulses) start again empty, as in a built
  scene: their ids name edges and slots that the reflection renumbers.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from engine.scene import ARENA_LEFT, ARENA_RIGHT
from engine.state import Bodies, ContactCache, Joints, State, Thrusters

CENTRE_X = 0.5 * (ARENA_LEFT + ARENA_RIGHT)
"""[m] The mirror line x = 2.5, the arena's vertical centre line."""
LEFT_WALL, RIGHT_WALL = 1, 2
"""The arena slots of the walls the reflection swaps."""


def mirror_state(state: State) -> State:
    """The mirror image of one scene (no batch axis; vmap it for a batch). Pure and jittable; numpy leaves come
    back as device arrays."""
    state = jax.tree.map(jnp.asarray, state)
    n = state.bodies.position.shape[0]
    order = jnp.arange(n).at[LEFT_WALL].set(RIGHT_WALL).at[RIGHT_WALL].set(LEFT_WALL)  # an involution
    slotted = jax.tree.map(lambda x: x[order], state.bodies)
    return State(
        bodies=_active_only(_mirror_bodies(slotted), slotted),
        joints=_active_only(_mirror_joints(state.joints, order), state.joints),
        thrusters=_active_only(_mirror_thrusters(state.thrusters, order), state.thrusters),
        contacts=ContactCache(  # empty, as a built scene's
            normal_impulse=jnp.zeros_like(state.contacts.normal_impulse),
            tangent_impulse=jnp.zeros_like(state.contacts.tangent_impulse),
            feature=jnp.full_like(state.contacts.feature, -1),
        ),
        gravity=state.gravity * jnp.array([-1.0, 1.0], state.gravity.dtype),
    )


def mirror_motor_actions(motor_actions: jax.Array) -> jax.Array:
    """Engine motor actions (J,) in [-1, 1] for the mirror image: the same motors, the other way."""
    return -motor_actions


def _active_only(mirrored, original):
    """`mirrored` where its slot is active, `original` in the empty slots (left as they were built; the bodies'
    `original` is already in the mirror's slot order)."""
    keep = lambda new, old: jnp.where(mirrored.active.reshape((-1,) + (1,) * (new.ndim - 1)), new, old)  # noqa: E731
    return jax.tree.map(keep, mirrored, original)


def _flip_x(xy: jax.Array) -> jax.Array:
    """Negate the x of (..., 2) vectors."""
    return xy * jnp.array([-1.0, 1.0], xy.dtype)


def _mirror_bodies(b: Bodies) -> Bodies:
    return b.replace(
        position=b.position.at[:, 0].set(2.0 * CENTRE_X - b.position[:, 0]),
        angle=-b.angle,
        velocity=_flip_x(b.velocity),
        angular_velocity=-b.angular_velocity,
        vertices=_reverse_vertices(_flip_x(b.vertices), b.num_vertices),
    )


def _reverse_vertices(vertices: jax.Array, num_vertices: jax.Array) -> jax.Array:
    """(N, 4, 2) vertices in reverse order (a reflection turns counter-clockwise into clockwise): a quad
    v0 v1 v2 v3 -> v1 v0 v3 v2, a triangle v0 v1 v2 (v0) -> v1 v0 v2 (v1). Starting from v1 keeps a box's
    vertices in the order it was built with (bottom-left first), so the arena stays the arena as built.
    Circles' zero rows stay zero."""
    quad, triangle = jnp.array([1, 0, 3, 2]), jnp.array([1, 0, 2, 1])
    index = jnp.where((num_vertices == 3)[:, None], triangle, quad)
    return jnp.take_along_axis(vertices, index[:, :, None], axis=1)


def _mirror_joints(j: Joints, order: jax.Array) -> Joints:
    return j.replace(
        body_a=order[j.body_a],
        body_b=order[j.body_b],
        anchor_a=_flip_x(j.anchor_a),
        anchor_b=_flip_x(j.anchor_b),
        ref_angle=-j.ref_angle,
        min_angle=-j.max_angle,
        max_angle=-j.min_angle,
        impulse=jnp.zeros_like(j.impulse),
        angular_impulse=jnp.zeros_like(j.angular_impulse),
        lower_impulse=jnp.zeros_like(j.lower_impulse),
        upper_impulse=jnp.zeros_like(j.upper_impulse),
    )


def _mirror_thrusters(t: Thrusters, order: jax.Array) -> Thrusters:
    return t.replace(body=order[t.body], anchor=_flip_x(t.anchor), angle=jnp.pi - t.angle)
