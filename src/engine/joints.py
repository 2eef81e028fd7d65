"""Joint constraints: revolute point constraint, fixed-joint angle, revolute limits, position correction.

Velocities are packed as `v3` (N, 3) rows (vx, vy, omega); each update gathers and scatter-adds both bodies.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from flax import struct

from engine.config import Params, Static
from engine.geometry import cross, cross_scalar_vector, rotate
from engine.state import Bodies, Joints


@struct.dataclass
class JointConstraints:
    """Per-step joint data, J slots.

    Attributes:
        bodies: (J, 2) int32 body slots a, b.
        r_a, r_b: (J, 2) world lever arms from each centre of mass to its anchor [m].
        inv_mass_a, inv_mass_b, inv_inertia_a, inv_inertia_b: (J,).
        point_on, angle_on, lower_on, upper_on: (J,) float32 1/0 masks of the constraint rows.
        point_inverse_mass: (J, 2, 2) inverse of the point constraint's effective-mass matrix K^-1 [kg].
        point_bias: (J, 2) velocity bias of the point constraint [m/s].
        angular_mass: (J,) 1 / (I_a^-1 + I_b^-1) [kg m^2].
        angle_bias, lower_bias, upper_bias: (J,) velocity biases of the angular rows [rad/s].
        impulse, angular_impulse, lower_impulse, upper_impulse: warm-start impulses.
    """

    bodies: jax.Array
    r_a: jax.Array
    r_b: jax.Array
    inv_mass_a: jax.Array
    inv_mass_b: jax.Array
    inv_inertia_a: jax.Array
    inv_inertia_b: jax.Array
    point_on: jax.Array
    angle_on: jax.Array
    lower_on: jax.Array
    upper_on: jax.Array
    point_inverse_mass: jax.Array
    point_bias: jax.Array
    angular_mass: jax.Array
    angle_bias: jax.Array
    lower_bias: jax.Array
    upper_bias: jax.Array
    impulse: jax.Array
    angular_impulse: jax.Array
    lower_impulse: jax.Array
    upper_impulse: jax.Array


def joint_usable(joints: Joints, bodies: Bodies) -> jax.Array:
    """(J,) bool: the joint is active, joins two different bodies, and both bodies are active."""
    return (
        joints.active & (joints.body_a != joints.body_b) & bodies.active[joints.body_a] & bodies.active[joints.body_b]
    )


def _point_inverse_mass(m_a, m_b, i_a, i_b, r_a, r_b):
    """Inverse of K = (m_a + m_b) I + i_a [r_a]x^T [r_a]x + i_b [r_b]x^T [r_b]x, batched; 0 where singular."""
    k11 = m_a + m_b + i_a * r_a[..., 1] ** 2 + i_b * r_b[..., 1] ** 2
    k12 = -i_a * r_a[..., 0] * r_a[..., 1] - i_b * r_b[..., 0] * r_b[..., 1]
    k22 = m_a + m_b + i_a * r_a[..., 0] ** 2 + i_b * r_b[..., 0] ** 2
    det = k11 * k22 - k12 * k12
    ok = det > 1e-12
    inv_det = jnp.where(ok, 1.0 / jnp.where(ok, det, 1.0), 0.0)
    row0 = jnp.stack([k22, -k12], -1)
    row1 = jnp.stack([-k12, k11], -1)
    return jnp.stack([row0, row1], -2) * inv_det[..., None, None]


def _angular_mass(i_a, i_b):
    total = i_a + i_b
    return jnp.where(total > 0, 1.0 / jnp.where(total > 0, total, 1.0), 0.0)


def prepare_joints(
    static: Static,
    params: Params,
    bodies: Bodies,
    joints: Joints,
    inv_mass: jax.Array,
    inv_inertia: jax.Array,
) -> JointConstraints:
    """Lever arms, effective masses and biases of every joint row from the positions at the start of the step."""
    a, b = joints.body_a, joints.body_b
    usable = joint_usable(joints, bodies)
    r_a = rotate(joints.anchor_a, bodies.angle[a])
    r_b = rotate(joints.anchor_b, bodies.angle[b])
    m_a, m_b, i_a, i_b = inv_mass[a], inv_mass[b], inv_inertia[a], inv_inertia[b]
    drift = bodies.position[b] + r_b - bodies.position[a] - r_a
    relative_angle = bodies.angle[b] - bodies.angle[a]

    revolute_limits = usable & ~joints.fixed & joints.has_limits
    lower_gap = relative_angle - joints.min_angle
    upper_gap = joints.max_angle - relative_angle

    def limit_bias(gap):
        return jnp.where(gap > 0, gap / params.dt, params.limit_bias * gap)

    on = usable.astype(jnp.float32)
    return JointConstraints(
        bodies=jnp.stack([a, b], axis=-1),
        r_a=r_a,
        r_b=r_b,
        inv_mass_a=m_a,
        inv_mass_b=m_b,
        inv_inertia_a=i_a,
        inv_inertia_b=i_b,
        point_on=on,
        angle_on=on * joints.fixed,
        lower_on=revolute_limits.astype(jnp.float32),
        upper_on=revolute_limits.astype(jnp.float32),
        point_inverse_mass=_point_inverse_mass(m_a, m_b, i_a, i_b, r_a, r_b),
        point_bias=params.joint_velocity_bias * drift,
        angular_mass=_angular_mass(i_a, i_b),
        angle_bias=params.fixed_joint_bias * (relative_angle - joints.ref_angle),
        lower_bias=limit_bias(lower_gap),
        upper_bias=limit_bias(upper_gap),
        impulse=joints.impulse * on[:, None],
        angular_impulse=joints.angular_impulse * on * joints.fixed,
        lower_impulse=jnp.where(revolute_limits, joints.lower_impulse, 0.0),
        upper_impulse=jnp.where(revolute_limits, joints.upper_impulse, 0.0),
    )


def _apply(c, v3, impulse, torque):
    """Apply a point impulse (2,) at the anchors (+ on b, - on a) and an angular impulse (+ on b, - on a)."""
    dv_a = jnp.concatenate([-c.inv_mass_a * impulse, (-c.inv_inertia_a * (cross(c.r_a, impulse) + torque))[None]])
    dv_b = jnp.concatenate([c.inv_mass_b * impulse, (c.inv_inertia_b * (cross(c.r_b, impulse) + torque))[None]])
    return v3.at[c.bodies].add(jnp.stack([dv_a, dv_b]))


def warm_start_joints(c: JointConstraints, v3: jax.Array) -> jax.Array:
    """Apply last step's joint impulses, all joints at once (a sum). v3: (N, 3)."""
    torque = c.angular_impulse + c.lower_impulse - c.upper_impulse
    dv_a = jnp.concatenate(
        [
            -c.inv_mass_a[:, None] * c.impulse,
            (-c.inv_inertia_a * (cross(c.r_a, c.impulse) + torque))[:, None],
        ],
        -1,
    )
    dv_b = jnp.concatenate(
        [c.inv_mass_b[:, None] * c.impulse, (c.inv_inertia_b * (cross(c.r_b, c.impulse) + torque))[:, None]],
        -1,
    )
    return v3.at[c.bodies].add(jnp.stack([dv_a, dv_b], axis=1))


def solve_joint(c: JointConstraints, v3: jax.Array, impulse, angular_impulse, lower_impulse, upper_impulse):
    """One Gauss-Seidel update of one joint (`c` sliced to a single joint): angle rows, then the point.

    Returns the new v3 (N, 3) and the accumulated impulses.
    """
    v_a, v_b = v3[c.bodies]
    w_rel = v_b[2] - v_a[2]

    d_angle = -c.angular_mass * (w_rel + c.angle_bias) * c.angle_on
    w_rel = w_rel + (c.inv_inertia_a + c.inv_inertia_b) * d_angle
    new_lower = jnp.maximum(lower_impulse - c.angular_mass * (w_rel + c.lower_bias), 0.0) * c.lower_on
    d_lower = new_lower - lower_impulse
    w_rel = w_rel + (c.inv_inertia_a + c.inv_inertia_b) * d_lower
    new_upper = jnp.maximum(upper_impulse - c.angular_mass * (-w_rel + c.upper_bias), 0.0) * c.upper_on
    d_upper = new_upper - upper_impulse
    torque = d_angle + d_lower - d_upper

    w_a = v_a[2] - c.inv_inertia_a * torque
    w_b = v_b[2] + c.inv_inertia_b * torque
    rel = v_b[:2] + cross_scalar_vector(w_b, c.r_b) - v_a[:2] - cross_scalar_vector(w_a, c.r_a)
    d_point = -(c.point_inverse_mass @ (rel + c.point_bias)) * c.point_on
    v3 = _apply(c, v3, d_point, torque)
    return v3, impulse + d_point, angular_impulse + d_angle, new_lower, new_upper


def correct_joint_positions(static: Static, params: Params, bodies: Bodies, joints: Joints, inv_mass, inv_inertia):
    """Project joint drift away after integration, one Gauss-Seidel pass (`joint_position_correction` of it).

    Moves positions (N, 2) [m] and angles (N,) [rad] only; velocities are untouched.
    """
    usable = joint_usable(joints, bodies).astype(jnp.float32)
    position, angle = bodies.position, bodies.angle
    beta = params.joint_position_correction
    for j in range(static.num_joints):
        a, b = joints.body_a[j], joints.body_b[j]
        m_a, m_b, i_a, i_b = inv_mass[a], inv_mass[b], inv_inertia[a], inv_inertia[b]
        r_a = rotate(joints.anchor_a[j], angle[a])
        r_b = rotate(joints.anchor_b[j], angle[b])
        drift = position[b] + r_b - position[a] - r_a
        p = -beta * usable[j] * (_point_inverse_mass(m_a, m_b, i_a, i_b, r_a, r_b) @ drift)
        fixed = usable[j] * joints.fixed[j]
        turn = -beta * fixed * _angular_mass(i_a, i_b) * (angle[b] - angle[a] - joints.ref_angle[j])
        position = position.at[a].add(-m_a * p).at[b].add(m_b * p)
        angle = angle.at[a].add(-i_a * (cross(r_a, p) + turn)).at[b].add(i_b * (cross(r_b, p) + turn))
    return bodies.replace(position=position, angle=angle)
