"""The velocity solver: Gauss-Seidel sweeps over joints then contact points, with accumulated impulses.

Per sweep the constraints are visited in a fixed order (joints 0..J-1, then contacts 0..K-1); the sweep
is unrolled and `Static.solver_iterations` sweeps run in a `fori_loop`, so compile size grows with J + K
but not with the iteration count.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from flax import struct

from engine.config import Static
from engine.contacts import ContactConstraints, solve_contact
from engine.joints import JointConstraints, solve_joint


@struct.dataclass
class Impulses:
    """Accumulated impulses of one step, one tuple entry per constraint (unstacked for the unrolled sweep)."""

    contact_normal: tuple
    contact_tangent: tuple
    joint_point: tuple
    joint_angle: tuple
    joint_lower: tuple
    joint_upper: tuple


def _unstack(tree, count: int) -> list:
    return [jax.tree.map(lambda x, i=i: x[i], tree) for i in range(count)]


def solve_velocities(
    static: Static, contacts: ContactConstraints, joints: JointConstraints, v3: jax.Array
) -> tuple[jax.Array, Impulses]:
    """Run the sweeps. v3: (N, 3) velocities after warm starting. Returns v3 and the accumulated impulses."""
    num_contacts = contacts.slot.shape[0]
    contact_rows = _unstack(contacts, num_contacts)
    joint_rows = _unstack(joints, static.num_joints)
    start = Impulses(
        contact_normal=tuple(c.normal_impulse for c in contact_rows),
        contact_tangent=tuple(c.tangent_impulse for c in contact_rows),
        joint_point=tuple(j.impulse for j in joint_rows),
        joint_angle=tuple(j.angular_impulse for j in joint_rows),
        joint_lower=tuple(j.lower_impulse for j in joint_rows),
        joint_upper=tuple(j.upper_impulse for j in joint_rows),
    )

    def sweep(_, carry):
        v3, imp = carry
        point, angle, lower, upper = (
            list(x) for x in (imp.joint_point, imp.joint_angle, imp.joint_lower, imp.joint_upper)
        )
        for j, row in enumerate(joint_rows):
            v3, point[j], angle[j], lower[j], upper[j] = solve_joint(row, v3, point[j], angle[j], lower[j], upper[j])
        normal, tangent = list(imp.contact_normal), list(imp.contact_tangent)
        for k, row in enumerate(contact_rows):
            v3, normal[k], tangent[k] = solve_contact(row, v3, normal[k], tangent[k])
        return v3, Impulses(tuple(normal), tuple(tangent), tuple(point), tuple(angle), tuple(lower), tuple(upper))

    return jax.lax.fori_loop(0, static.solver_iterations, sweep, (v3, start))


def stack_values(values: tuple, like: jax.Array) -> jax.Array:
    """Stack a tuple of per-constraint values back into an array shaped like `like`."""
    return jnp.stack(values) if values else jnp.zeros_like(like)
