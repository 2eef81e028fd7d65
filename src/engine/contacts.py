"""Contact constraints: pick the points to solve, prepare their Jacobians, solve one, store impulses.

Velocities are packed as `v3`: (N, 3) rows (vx, vy, omega). A constraint row has a Jacobian for each body,
`j_a`, `j_b`: (3,), and inverse-mass-weighted copies `w_a`, `w_b` so an impulse lambda changes
v_a by w_a * lambda. Each update gathers both bodies' rows at once and scatter-adds both changes at once.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from flax import struct

from engine.config import Params, Static
from engine.geometry import cross
from engine.narrowphase import Manifold
from engine.pairs import pair_table
from engine.state import Bodies, ContactCache


@struct.dataclass
class ContactConstraints:
    """The K contact points solved this step.

    Attributes:
        slot: (K,) int32 candidate point index in the manifold / cache.
        active: (K,) bool.
        bodies: (K, 2) int32 body slots a, b.
        jn_a, jn_b, jt_a, jt_b: (K, 3) normal and tangent Jacobian rows.
        wn_a, wn_b, wt_a, wt_b: (K, 3) the rows weighted by inverse mass and inertia.
        normal_mass, tangent_mass: (K,) effective masses [kg]; 0 for inactive points.
        friction: (K,) friction coefficient [1].
        target: (K,) lowest allowed normal velocity after the solve [m/s] (bias, speculation, bounce).
        normal_impulse, tangent_impulse: (K,) warm-start impulses [N s].
    """

    slot: jax.Array
    active: jax.Array
    bodies: jax.Array
    jn_a: jax.Array
    jn_b: jax.Array
    jt_a: jax.Array
    jt_b: jax.Array
    wn_a: jax.Array
    wn_b: jax.Array
    wt_a: jax.Array
    wt_b: jax.Array
    normal_mass: jax.Array
    tangent_mass: jax.Array
    friction: jax.Array
    target: jax.Array
    normal_impulse: jax.Array
    tangent_impulse: jax.Array


def num_solved_contacts(static: Static) -> int:
    """K: the contact points solved per step (all candidates when `max_contacts` is 0 or larger)."""
    m = pair_table(static).num_points
    return m if static.max_contacts == 0 else min(static.max_contacts, m)


def select_contacts(static: Static, manifold: Manifold, solvable: jax.Array) -> tuple[jax.Array, jax.Array]:
    """Choose K candidate points, deepest first. Returns slots (K,) and the number of solvable points dropped."""
    k, m = num_solved_contacts(static), pair_table(static).num_points
    if k == m:
        slots = jnp.arange(m, dtype=jnp.int32)
    else:
        _, slots = jax.lax.top_k(jnp.where(solvable, -manifold.separation, -jnp.inf), k)
    dropped = solvable.sum() - solvable[slots].sum()
    return slots.astype(jnp.int32), dropped.astype(jnp.int32)


def _rows(normal, r_a, r_b):
    """Jacobian rows (3,) of relative velocity along `normal` at lever arms r_a, r_b (each (..., 2))."""
    j_a = jnp.concatenate([-normal, -cross(r_a, normal)[..., None]], axis=-1)
    j_b = jnp.concatenate([normal, cross(r_b, normal)[..., None]], axis=-1)
    return j_a, j_b


def prepare_contacts(
    static: Static,
    params: Params,
    bodies: Bodies,
    inv_mass3: jax.Array,
    v3: jax.Array,
    manifold: Manifold,
    solvable: jax.Array,
    cache: ContactCache,
) -> tuple[ContactConstraints, jax.Array]:
    """Build the K contact constraints of this step from the manifold (positions at the start of the step).

    Args:
        inv_mass3: (N, 3) inverse mass, inverse mass, inverse inertia.
        v3: (N, 3) velocities after gravity and actuators.
        solvable: (M,) bool candidate points that may be solved.
    Returns the constraints and the number of solvable points that did not fit.
    """
    table = pair_table(static)
    slots, dropped = select_contacts(static, manifold, solvable)
    pair = jnp.asarray(table.point_pair)[slots]
    a, b = jnp.asarray(table.a)[pair], jnp.asarray(table.b)[pair]
    active = solvable[slots]
    normal, point, sep = manifold.normal[slots], manifold.point[slots], manifold.separation[slots]
    r_a, r_b = point - bodies.position[a], point - bodies.position[b]
    tangent = jnp.stack([-normal[:, 1], normal[:, 0]], axis=-1)
    jn_a, jn_b = _rows(normal, r_a, r_b)
    jt_a, jt_b = _rows(tangent, r_a, r_b)
    m_a, m_b = inv_mass3[a], inv_mass3[b]
    wn_a, wn_b, wt_a, wt_b = m_a * jn_a, m_b * jn_b, m_a * jt_a, m_b * jt_b

    def effective_mass(j_a, j_b, w_a, w_b):
        k = jnp.sum(j_a * w_a, -1) + jnp.sum(j_b * w_b, -1)
        return jnp.where(active & (k > 1e-12), 1.0 / jnp.where(k > 1e-12, k, 1.0), 0.0)

    vn = jnp.sum(jn_a * v3[a], -1) + jnp.sum(jn_b * v3[b], -1)
    push = jnp.where(sep > 0, -sep / params.dt, params.baumgarte / params.dt * jnp.maximum(-sep - params.slop, 0.0))
    restitution = jnp.minimum(bodies.restitution[a], bodies.restitution[b])
    hits = (vn < -params.restitution_threshold) & (sep + vn * params.dt < 0)
    target = jnp.where(hits, jnp.maximum(push, -restitution * vn), push)
    friction = params.friction_scale * jnp.sqrt(bodies.friction[a] ** 2 + bodies.friction[b] ** 2)

    same_feature = active & (cache.feature[slots] == manifold.feature[slots])
    constraints = ContactConstraints(
        slot=slots,
        active=active,
        bodies=jnp.stack([a, b], axis=-1),
        jn_a=jn_a,
        jn_b=jn_b,
        jt_a=jt_a,
        jt_b=jt_b,
        wn_a=wn_a,
        wn_b=wn_b,
        wt_a=wt_a,
        wt_b=wt_b,
        normal_mass=effective_mass(jn_a, jn_b, wn_a, wn_b),
        tangent_mass=effective_mass(jt_a, jt_b, wt_a, wt_b),
        friction=jnp.where(active, friction, 0.0),
        target=target,
        normal_impulse=jnp.where(same_feature, cache.normal_impulse[slots], 0.0),
        tangent_impulse=jnp.where(same_feature, cache.tangent_impulse[slots], 0.0),
    )
    return constraints, dropped


def warm_start_contacts(c: ContactConstraints, v3: jax.Array) -> jax.Array:
    """Apply last step's impulses of all K points at once (a sum, so order does not matter). v3: (N, 3)."""
    dv_a = c.wn_a * c.normal_impulse[:, None] + c.wt_a * c.tangent_impulse[:, None]
    dv_b = c.wn_b * c.normal_impulse[:, None] + c.wt_b * c.tangent_impulse[:, None]
    return v3.at[c.bodies].add(jnp.stack([dv_a, dv_b], axis=1))


def solve_contact(c: ContactConstraints, v3: jax.Array, normal_impulse, tangent_impulse):
    """One Gauss-Seidel update of one contact point (`c` sliced to a single point): friction, then normal.

    Returns the new v3 (N, 3) and the accumulated normal and tangent impulses [N s].
    """
    v_a, v_b = v3[c.bodies]
    vt = jnp.sum(c.jt_a * v_a + c.jt_b * v_b)
    limit = c.friction * normal_impulse
    new_t = jnp.clip(tangent_impulse - c.tangent_mass * vt, -limit, limit)
    d_t = new_t - tangent_impulse
    dv_a, dv_b = c.wt_a * d_t, c.wt_b * d_t

    vn = jnp.sum(c.jn_a * (v_a + dv_a) + c.jn_b * (v_b + dv_b))
    new_n = jnp.maximum(normal_impulse + c.normal_mass * (c.target - vn), 0.0)
    d_n = new_n - normal_impulse
    dv_a = dv_a + c.wn_a * d_n
    dv_b = dv_b + c.wn_b * d_n
    v3 = v3.at[c.bodies].add(jnp.stack([dv_a, dv_b]))
    return v3, new_n, new_t


def store_contact_impulses(
    static: Static, c: ContactConstraints, manifold: Manifold, normal_impulse, tangent_impulse
) -> ContactCache:
    """Write the solved impulses back to their candidate slots for the next step's warm start."""
    m = pair_table(static).num_points
    return ContactCache(
        normal_impulse=jnp.zeros(m).at[c.slot].set(jnp.where(c.active, normal_impulse, 0.0)),
        tangent_impulse=jnp.zeros(m).at[c.slot].set(jnp.where(c.active, tangent_impulse, 0.0)),
        feature=manifold.feature,
    )
