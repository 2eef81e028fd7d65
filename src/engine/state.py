"""Device state of one scene: bodies, joints, thrusters, the contact warm-start cache, and gravity.

Every array has a static leading capacity from `Static`; unused slots are inactive. A batch of scenes is
the same tree with one more leading axis (see `scene.stack`).
"""

from __future__ import annotations

import jax
from flax import struct


@struct.dataclass
class Bodies:
    """Rigid bodies. Slots [0, P) are polygons (0..3 the arena), [P, P + C) circles; N = P + C.

    Attributes:
        position: (N, 2) world-space centre of mass [m].
        angle: (N,) rotation [rad], counter-clockwise.
        velocity: (N, 2) linear velocity of the centre of mass [m/s].
        angular_velocity: (N,) [rad/s], counter-clockwise.
        vertices: (N, 4, 2) polygon vertices relative to the centre of mass in the body frame [m],
            counter-clockwise; a triangle repeats vertex 0 in slot 3. Zero for circles.
        num_vertices: (N,) int32, 3 or 4 for polygons, 0 for circles.
        radius: (N,) circle radius [m]; 0 for polygons.
        density: (N,) [kg/m^2].
        friction: (N,) material friction [1].
        restitution: (N,) material restitution [1].
        collision_mode: (N,) int32 in {0, 1, 2}: two bodies collide if either is 2 or both are non-zero.
        active: (N,) bool; inactive bodies do not move, collide or act.
        fixed: (N,) bool; fixed bodies have infinite mass (they still collide).
        role: (N,) int32 task role (0 neutral, 1 green, 2 blue, 3 red); the engine only carries it.
    """

    position: jax.Array
    angle: jax.Array
    velocity: jax.Array
    angular_velocity: jax.Array
    vertices: jax.Array
    num_vertices: jax.Array
    radius: jax.Array
    density: jax.Array
    friction: jax.Array
    restitution: jax.Array
    collision_mode: jax.Array
    active: jax.Array
    fixed: jax.Array
    role: jax.Array


@struct.dataclass
class Joints:
    """Revolute and fixed joints between two bodies. J slots.

    Attributes:
        body_a, body_b: (J,) int32 body slots.
        anchor_a, anchor_b: (J, 2) anchor relative to each centre of mass, in the body frame [m].
        fixed: (J,) bool; True welds the bodies at relative angle `ref_angle`, False is revolute.
        ref_angle: (J,) held relative angle angle_b - angle_a of a fixed joint [rad].
        motor_on: (J,) bool; a revolute joint with a motor follows action * motor_speed * base speed.
        motor_speed: (J,) motor speed scale [1].
        motor_power: (J,) motor power scale [1].
        has_limits: (J,) bool; revolute limits on angle_b - angle_a.
        min_angle, max_angle: (J,) limits [rad].
        active: (J,) bool.
        impulse: (J, 2) accumulated point impulse of the last step (warm start) [N s].
        angular_impulse: (J,) accumulated fixed-joint angular impulse [N m s].
        lower_impulse, upper_impulse: (J,) accumulated limit impulses [N m s].
    """

    body_a: jax.Array
    body_b: jax.Array
    anchor_a: jax.Array
    anchor_b: jax.Array
    fixed: jax.Array
    ref_angle: jax.Array
    motor_on: jax.Array
    motor_speed: jax.Array
    motor_power: jax.Array
    has_limits: jax.Array
    min_angle: jax.Array
    max_angle: jax.Array
    active: jax.Array
    impulse: jax.Array
    angular_impulse: jax.Array
    lower_impulse: jax.Array
    upper_impulse: jax.Array


@struct.dataclass
class Thrusters:
    """Thrusters pushing a body. T slots.

    Attributes:
        body: (T,) int32 body slot.
        anchor: (T, 2) point of application relative to the centre of mass, body frame [m].
        angle: (T,) direction of the push in the body frame [rad].
        power: (T,) power scale [1]; force = base_thruster_power * power * action [N].
        active: (T,) bool.
    """

    body: jax.Array
    anchor: jax.Array
    angle: jax.Array
    power: jax.Array
    active: jax.Array


@struct.dataclass
class ContactCache:
    """Impulses of the last step per candidate contact point (M slots, see `pairs.PairTable`).

    Attributes:
        normal_impulse: (M,) [N s].
        tangent_impulse: (M,) [N s].
        feature: (M,) int32 id of the features that made the point; warm start only reuses a matching id.
    """

    normal_impulse: jax.Array
    tangent_impulse: jax.Array
    feature: jax.Array


@struct.dataclass
class State:
    """Everything that changes between steps, for one scene.

    Attributes:
        bodies, joints, thrusters, contacts: see their classes.
        gravity: (2,) [m/s^2].
    """

    bodies: Bodies
    joints: Joints
    thrusters: Thrusters
    contacts: ContactCache
    gravity: jax.Array
