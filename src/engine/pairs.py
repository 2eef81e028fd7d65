"""Which body pairs are tested for contact: a static pair table per size, and a per-step filter.

The table lists every pair that can ever collide (arena-arena pairs are left out), grouped by kind:
polygon-polygon (2 candidate points each), polygon-circle (1 point, the polygon first) and circle-circle
(1 point). Point m belongs to pair `point_pair[m]`.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from engine.config import NUM_ARENA_POLYGONS, Static
from engine.state import Bodies, Joints


@dataclasses.dataclass(frozen=True)
class PairTable:
    """Static (numpy) pair layout for one `Static`.

    Attributes:
        a, b: (num_pairs,) body slots; kinds in order polygon-polygon, polygon-circle, circle-circle.
        num_pp, num_pc, num_cc: pairs of each kind.
        point_pair: (num_points,) the pair of each candidate contact point.
    """

    a: np.ndarray
    b: np.ndarray
    num_pp: int
    num_pc: int
    num_cc: int
    point_pair: np.ndarray

    @property
    def num_pairs(self) -> int:
        return len(self.a)

    @property
    def num_points(self) -> int:
        return len(self.point_pair)


@functools.cache
def pair_table(static: Static) -> PairTable:
    """The pair table of a size (cached; pure numpy, no tracing)."""
    p, c = static.num_polygons, static.num_circles
    pp = [(i, j) for i in range(p) for j in range(i + 1, p) if j >= NUM_ARENA_POLYGONS]
    pc = [(i, p + k) for k in range(c) for i in range(p)]
    cc = [(p + i, p + j) for i in range(c) for j in range(i + 1, c)]
    pairs = pp + pc + cc
    a = np.array([x for x, _ in pairs], dtype=np.int32)
    b = np.array([y for _, y in pairs], dtype=np.int32)
    point_pair = np.concatenate([np.repeat(np.arange(len(pp)), 2), len(pp) + np.arange(len(pc) + len(cc))]).astype(
        np.int32
    )
    return PairTable(a=a, b=b, num_pp=len(pp), num_pc=len(pc), num_cc=len(cc), point_pair=point_pair)


def joint_connectivity(joints: Joints, num_bodies: int) -> jax.Array:
    """(N, N) bool: bodies linked through any chain of active joints (transitive closure).

    Built from the adjacency matrix by repeated boolean squaring: ceil(log2 N) small matmuls.
    """
    onehot_a = jax.nn.one_hot(joints.body_a, num_bodies, dtype=jnp.float32) * joints.active[:, None]
    onehot_b = jax.nn.one_hot(joints.body_b, num_bodies, dtype=jnp.float32) * joints.active[:, None]
    adjacency = onehot_a.T @ onehot_b
    reach = ((adjacency + adjacency.T + jnp.eye(num_bodies)) > 0).astype(jnp.float32)
    for _ in range(max(1, int(np.ceil(np.log2(max(num_bodies, 2)))))):
        reach = ((reach @ reach) > 0).astype(jnp.float32)
    return reach > 0


def collidable_pairs(static: Static, bodies: Bodies, joints: Joints) -> jax.Array:
    """(num_pairs,) bool: both bodies active, the collision-mode rule allows it, and no joint chain links them."""
    table = pair_table(static)
    a, b = jnp.asarray(table.a), jnp.asarray(table.b)
    mode_a, mode_b = bodies.collision_mode[a], bodies.collision_mode[b]
    mode_ok = (mode_a == 2) | (mode_b == 2) | ((mode_a != 0) & (mode_b != 0))
    linked = joint_connectivity(joints, static.num_bodies)[a, b]
    return bodies.active[a] & bodies.active[b] & mode_ok & ~linked
