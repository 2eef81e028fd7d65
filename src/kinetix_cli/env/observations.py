"""Symbolic observations: per-entity feature rows, and the size-specific flat vector built from them.

Feature rows (shared by ``symbolic-flat`` and ``symbolic-entity``):

- shape (17): position (2) [m], velocity (2) [m/s], log(1 + inverse mass), log(1 + inverse inertia),
  density, tanh(omega / 10), one-hot role (4: neutral, green, blue, red), sin and cos of the angle,
  friction, restitution, fixed flag.
- polygon (26) = shape (17) + vertices (4 x 2, body frame [m], a triangle repeats vertex 0) + triangle flag.
- circle (18) = shape (17) + radius [m].
- joint (22), seen from body ``src`` towards body ``dst``: active, fixed, motor on, auto motor,
  one-hot motor binding (4), motor speed, motor power, has limits, min and max angle [rad] (of
  angle_dst - angle_src), anchor in the src frame (2) and in the dst frame (2) [m], sin and cos of the
  relative angle (2), the relative angle [rad], tanh(relative angular velocity / 10), reversed flag
  (1 when src is the joint's body_b).
- thruster (8): active, one-hot binding (2), power, anchor in the body frame (2) [m], direction in the
  body frame (cos, sin).

Inactive slots are all zeros. ``symbolic-flat`` concatenates: the floor and the non-arena polygon slots
(P - 3 rows of 26), circles (C x 18), joints a -> b with one-hot body_a and body_b (J x (22 + 2N)),
thrusters with a one-hot body (T x (8 + N)), and gravity_y / 10: 140 values at size s, 247 at m, 679 at l.

``symbolic-entity`` (`symbolic_entity`) keeps the rows apart with size-independent widths: polygons (P, 27),
circles (C, 19), joints once per direction (2J, 22) with src/dst entity indices, thrusters (T, 8) with their
body, per-entity masks, 4 attention channels (N, N) and gravity / 10; see `EntityObservation`.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from flax import struct

from engine import (
    NUM_ARENA_POLYGONS,
    Static,
    collidable_pairs,
    collide,
    joint_connectivity,
    mass_properties,
    pair_table,
    touching_matrix,
)
from kinetix_cli.constants import NUM_ATTENTION_CHANNELS, NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS, ROLE_NAMES
from kinetix_cli.env.level import Bindings

SHAPE_FEATURES = 17
POLYGON_FEATURES = 26
CIRCLE_FEATURES = 18
JOINT_FEATURES = 22
THRUSTER_FEATURES = 8

# Columns that models read by meaning (the layout above): a shape row's position, role and angle, a joint row's
# motor binding, a thruster row's binding, anchor and body-frame direction.
SHAPE_POSITION = slice(0, 2)
SHAPE_ROLE = slice(8, 12)
SHAPE_SIN, SHAPE_COS = 12, 13
JOINT_BINDING = slice(4, 8)
THRUSTER_BINDING = slice(1, 3)
THRUSTER_ANCHOR = slice(4, 6)
THRUSTER_DIRECTION = slice(6, 8)


def shape_features(static: Static, physics) -> jax.Array:
    """(N, 17) common features of every body slot (see the module docstring); inactive rows are zero."""
    b = physics.bodies
    inv_mass, inv_inertia = mass_properties(b, static.num_polygons)
    rows = jnp.concatenate(
        [
            b.position,
            b.velocity,
            jnp.log1p(inv_mass)[:, None],
            jnp.log1p(inv_inertia)[:, None],
            b.density[:, None],
            jnp.tanh(b.angular_velocity / 10.0)[:, None],
            jax.nn.one_hot(b.role, len(ROLE_NAMES)),
            jnp.sin(b.angle)[:, None],
            jnp.cos(b.angle)[:, None],
            b.friction[:, None],
            b.restitution[:, None],
            b.fixed[:, None].astype(jnp.float32),
        ],
        axis=-1,
    )
    return jnp.where(b.active[:, None], rows, 0.0)


def polygon_features(static: Static, physics, shapes: jax.Array) -> jax.Array:
    """(P, 26) polygon rows from the (N, 17) shape rows."""
    p = static.num_polygons
    b = physics.bodies
    extra = jnp.concatenate(
        [b.vertices[:p].reshape(p, 8), (b.num_vertices[:p] == 3)[:, None].astype(jnp.float32)], axis=-1
    )
    return jnp.concatenate([shapes[:p], jnp.where(b.active[:p, None], extra, 0.0)], axis=-1)


def circle_features(static: Static, physics, shapes: jax.Array) -> jax.Array:
    """(C, 18) circle rows from the (N, 17) shape rows."""
    p = static.num_polygons
    b = physics.bodies
    return jnp.concatenate([shapes[p:], jnp.where(b.active[p:], b.radius[p:], 0.0)[:, None]], axis=-1)


def joint_features(physics, bindings: Bindings, reverse: bool) -> jax.Array:
    """(J, 22) joint rows seen from body_a (reverse=False) or from body_b (reverse=True)."""
    j, b = physics.joints, physics.bodies
    src, dst = (j.body_b, j.body_a) if reverse else (j.body_a, j.body_b)
    anchor_src, anchor_dst = (j.anchor_b, j.anchor_a) if reverse else (j.anchor_a, j.anchor_b)
    sign = -1.0 if reverse else 1.0
    lo, hi = (-j.max_angle, -j.min_angle) if reverse else (j.min_angle, j.max_angle)
    relative = b.angle[dst] - b.angle[src]
    relative_omega = b.angular_velocity[dst] - b.angular_velocity[src]
    motor = j.motor_on & ~j.fixed
    f = lambda x: jnp.asarray(x, jnp.float32)[:, None]  # noqa: E731
    rows = jnp.concatenate(
        [
            f(j.active),
            f(j.fixed),
            f(motor),
            f(motor & bindings.motor_auto),
            jax.nn.one_hot(bindings.motor, NUM_MOTOR_BINDINGS) * f(motor & ~bindings.motor_auto),
            f(j.motor_speed * motor),
            f(j.motor_power * motor),
            f(j.has_limits),
            f(jnp.where(j.has_limits, lo, 0.0)),
            f(jnp.where(j.has_limits, hi, 0.0)),
            anchor_src,
            anchor_dst,
            f(jnp.sin(relative)),
            f(jnp.cos(relative)),
            f(relative),
            f(jnp.tanh(relative_omega / 10.0)),
            f(jnp.full_like(relative, sign < 0)),
        ],
        axis=-1,
    )
    return jnp.where(j.active[:, None], rows, 0.0)


def thruster_features(physics, bindings: Bindings) -> jax.Array:
    """(T, 8) thruster rows."""
    t = physics.thrusters
    rows = jnp.concatenate(
        [
            t.active[:, None].astype(jnp.float32),
            jax.nn.one_hot(bindings.thruster, NUM_THRUSTER_BINDINGS),
            t.power[:, None],
            t.anchor,
            jnp.cos(t.angle)[:, None],
            jnp.sin(t.angle)[:, None],
        ],
        axis=-1,
    )
    return jnp.where(t.active[:, None], rows, 0.0)


def flat_size(static: Static) -> int:
    """Length of the ``symbolic-flat`` vector of a size."""
    n = static.num_bodies
    return (
        (static.num_polygons - NUM_ARENA_POLYGONS + 1) * POLYGON_FEATURES
        + static.num_circles * CIRCLE_FEATURES
        + static.num_joints * (JOINT_FEATURES + 2 * n)
        + static.num_thrusters * (THRUSTER_FEATURES + n)
        + 1
    )


def symbolic_flat(static: Static, physics, bindings: Bindings) -> jax.Array:
    """(flat_size(static),) float32 observation of one scene (layout in the module docstring)."""
    n = static.num_bodies
    shapes = shape_features(static, physics)
    polygons = polygon_features(static, physics, shapes)
    polygons = jnp.concatenate([polygons[:1], polygons[NUM_ARENA_POLYGONS:]])
    joints = physics.joints
    joint_rows = jnp.concatenate(
        [
            joint_features(physics, bindings, reverse=False),
            jax.nn.one_hot(joints.body_a, n) * joints.active[:, None],
            jax.nn.one_hot(joints.body_b, n) * joints.active[:, None],
        ],
        axis=-1,
    )
    thrusters = physics.thrusters
    thruster_rows = jnp.concatenate(
        [thruster_features(physics, bindings), jax.nn.one_hot(thrusters.body, n) * thrusters.active[:, None]], axis=-1
    )
    parts = [
        polygons.reshape(-1),
        circle_features(static, physics, shapes).reshape(-1),
        joint_rows.reshape(-1),
        thruster_rows.reshape(-1),
        physics.gravity[1:] / 10.0,
    ]
    return jnp.concatenate(parts).astype(jnp.float32)


# --- symbolic-entity ------------------------------------------------------------------------------
ENTITY_POLYGON_FEATURES = POLYGON_FEATURES + 1
ARENA_SIDES = range(1, NUM_ARENA_POLYGONS)
"""The polygon slots of the arena's walls and ceiling: always masked in a ``symbolic-entity`` observation (models
may leave their rows out)."""

ENTITY_CIRCLE_FEATURES = CIRCLE_FEATURES + 1
CONTACT_DISTANCE = 0.01
"""Two collidable shapes count as in contact (attention channel 3) at a gap of at most this [m]."""


@struct.dataclass
class EntityObservation:
    """The ``symbolic-entity`` observation of one scene: size-independent feature widths, one row per slot.

    Entity index = body slot: polygons [0, P) then circles [P, P + C), N = P + C. Masked rows are all zeros.

    Attributes:
        polygons: (P, 27) float32 polygon rows (26, see the module docstring) + collision_mode / 2.
        circles: (C, 19) float32 circle rows (18) + collision_mode / 2.
        joints: (2J, 22) float32 joint rows: J rows seen from body_a (reverse=False), then the same J joints
            seen from body_b (reverse=True, limits mirrored to (-max, -min)).
        joint_src, joint_dst: (2J,) int32 entity indices of each joint row's src and dst body.
        thrusters: (T, 8) float32 thruster rows.
        thruster_body: (T,) int32 entity index of each thruster's body.
        polygon_mask: (P,) bool active polygon; the arena walls and ceiling (slots 1..3) are always False, the
            floor (slot 0) is True since it can carry a role.
        circle_mask: (C,) bool active circle.
        joint_mask: (2J,) bool active joint row.
        thruster_mask: (T,) bool active thruster.
        attention_mask: (4, N, N) bool between unmasked shapes, diagonal included, False for masked shapes:
            0 every pair; 1 linked through any chain of active joints; 2 directly joined by a joint;
            3 in contact: a pair the engine would collide (collision-mode rule, not joint-linked) whose
            narrowphase gap is at most `CONTACT_DISTANCE` (overlap included), from the current positions.
        gravity: (2,) float32 gravity / 10 [10 m/s^2].
    """

    polygons: jax.Array
    circles: jax.Array
    joints: jax.Array
    joint_src: jax.Array
    joint_dst: jax.Array
    thrusters: jax.Array
    thruster_body: jax.Array
    polygon_mask: jax.Array
    circle_mask: jax.Array
    joint_mask: jax.Array
    thruster_mask: jax.Array
    attention_mask: jax.Array
    gravity: jax.Array


def shape_mask(static: Static, physics) -> jax.Array:
    """(N,) bool: active body slots other than the arena walls and ceiling (`ARENA_SIDES`)."""
    slots = jnp.arange(static.num_bodies)
    arena_side = (slots >= ARENA_SIDES.start) & (slots < ARENA_SIDES.stop)
    return physics.bodies.active & ~arena_side


def contact_matrix(static: Static, physics, distance: float = CONTACT_DISTANCE) -> jax.Array:
    """(N, N) symmetric bool, diagonal False: collidable pairs whose narrowphase gap is <= `distance` [m].

    Uses the engine's narrowphase and pair filter (`engine.pairs.collidable_pairs`) on the current positions,
    like `StepInfo.touching` but without a step (no speculative reach); arena-arena pairs are never set.
    """
    table = pair_table(static)
    n = static.num_bodies
    if table.num_pairs == 0:
        return jnp.zeros((n, n), bool)
    bodies = physics.bodies
    manifold = collide(static, bodies, jnp.full((table.num_pairs,), distance, jnp.float32))
    collidable = collidable_pairs(static, bodies, physics.joints)
    point_pair = jnp.asarray(table.point_pair)
    close = manifold.valid & (manifold.separation <= distance)
    touching = jnp.zeros(table.num_pairs, bool).at[point_pair].max(close) & collidable
    return touching_matrix(static, touching)


def attention_masks(static: Static, physics, mask: jax.Array) -> jax.Array:
    """(4, N, N) bool attention channels (see `EntityObservation.attention_mask`) for the (N,) shape mask."""
    n = static.num_bodies
    joints = physics.joints
    onehot_a = jax.nn.one_hot(joints.body_a, n, dtype=jnp.float32) * joints.active[:, None]
    onehot_b = jax.nn.one_hot(joints.body_b, n, dtype=jnp.float32) * joints.active[:, None]
    adjacency = onehot_a.T @ onehot_b
    eye = jnp.eye(n, dtype=bool)
    direct = (adjacency + adjacency.T) > 0
    channels = jnp.stack(
        [
            jnp.ones((n, n), bool),
            joint_connectivity(joints, n),
            direct | eye,
            contact_matrix(static, physics) | eye,
        ]
    )
    return channels & (mask[:, None] & mask[None, :])[None]


def symbolic_entity(static: Static, physics, bindings: Bindings, attention: bool = True) -> EntityObservation:
    """The ``symbolic-entity`` observation of one scene (layout in `EntityObservation`); jittable, vmappable.
    `attention` False leaves `attention_mask` all False, without its contact test (for models that do not read
    it)."""
    p = static.num_polygons
    b, j, t = physics.bodies, physics.joints, physics.thrusters
    shapes = shape_features(static, physics)
    mode = jnp.where(b.active, b.collision_mode.astype(jnp.float32) / 2.0, 0.0)[:, None]
    polygons = jnp.concatenate([polygon_features(static, physics, shapes), mode[:p]], axis=-1)
    circles = jnp.concatenate([circle_features(static, physics, shapes), mode[p:]], axis=-1)
    joints = jnp.concatenate(
        [joint_features(physics, bindings, reverse=False), joint_features(physics, bindings, reverse=True)]
    )
    mask = shape_mask(static, physics)
    return EntityObservation(
        polygons=jnp.where(mask[:p, None], polygons, 0.0).astype(jnp.float32),
        circles=jnp.where(mask[p:, None], circles, 0.0).astype(jnp.float32),
        joints=joints.astype(jnp.float32),
        joint_src=jnp.concatenate([j.body_a, j.body_b]).astype(jnp.int32),
        joint_dst=jnp.concatenate([j.body_b, j.body_a]).astype(jnp.int32),
        thrusters=thruster_features(physics, bindings).astype(jnp.float32),
        thruster_body=t.body.astype(jnp.int32),
        polygon_mask=mask[:p],
        circle_mask=mask[p:],
        joint_mask=jnp.concatenate([j.active, j.active]),
        thruster_mask=t.active,
        attention_mask=attention_masks(static, physics, mask)
        if attention
        else jnp.zeros((NUM_ATTENTION_CHANNELS, static.num_bodies, static.num_bodies), bool),
        gravity=(physics.gravity / 10.0).astype(jnp.float32),
    )


def used_bindings(obs: EntityObservation) -> jax.Array:
    """(..., 6) bool: which action bindings move something in the scene, motor bindings 0-3 (a non-auto motor of an
    active joint on that binding) then thruster bindings 0-1 (an active thruster on it); any leading batch shape.
    The policies of `rl.networks` fix the action entries of the others at "off" (`model.mask_unused_actions`)."""
    motors = jnp.any((obs.joints[..., JOINT_BINDING] > 0.5) & obs.joint_mask[..., None], axis=-2)
    thrusters = jnp.any((obs.thrusters[..., THRUSTER_BINDING] > 0.5) & obs.thruster_mask[..., None], axis=-2)
    return jnp.concatenate([motors, thrusters], axis=-1)
