"""Narrowphase: candidate contact points for every pair in the pair table.

Kernels are written for one pair and vmapped over the pairs of their kind. Normals point from body a to
body b; separation is negative when the bodies overlap. Points are created up to
`Params.speculative_distance` before touching (speculative contacts).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from flax import struct

from engine.config import Static
from engine.geometry import edge_normals, rotate
from engine.pairs import pair_table
from engine.state import Bodies

_REFERENCE_FACE_TOLERANCE = 5e-4  # prefer polygon a's face unless b's is clearly better [m]


@struct.dataclass
class Manifold:
    """Candidate contact points, M = `pair_table(static).num_points`.

    Attributes:
        normal: (M, 2) unit normal from body a to body b.
        point: (M, 2) world contact point, midway between the two surfaces [m].
        separation: (M,) signed gap along the normal, negative when overlapping [m].
        feature: (M,) int32 id of the features that produced the point (for warm starting).
        valid: (M,) bool; within the speculative distance (pair filtering is applied later).
    """

    normal: jax.Array
    point: jax.Array
    separation: jax.Array
    feature: jax.Array
    valid: jax.Array


def world_polygons(static: Static, bodies: Bodies) -> tuple[jax.Array, jax.Array, jax.Array]:
    """World vertices (P, 4, 2) [m], outward unit normals (P, 4, 2) and valid-edge mask (P, 4) of the polygons."""
    p = static.num_polygons
    angle = bodies.angle[:p, None]
    verts = bodies.position[:p, None, :] + rotate(bodies.vertices[:p], angle)
    local_normals, valid = edge_normals(bodies.vertices[:p], bodies.num_vertices[:p])
    return verts, rotate(local_normals, angle), valid


def _max_separation(verts1, normals1, valid1, verts2):
    """Largest over edges of polygon 1 of the smallest signed distance of polygon 2's vertices: (sep, edge)."""
    dist = normals1 @ verts2.T - jnp.sum(normals1 * verts1, axis=-1)[:, None]  # (edge of 1, vertex of 2)
    per_edge = jnp.where(valid1, dist.min(axis=1), -jnp.inf)
    edge = jnp.argmax(per_edge)
    return per_edge[edge], edge


def _clip_segment(p0, p1, normal, offset):
    """Keep the part of segment p0-p1 with dot(normal, p) <= offset; returns (q0, q1, non_empty)."""
    d0 = normal @ p0 - offset
    d1 = normal @ p1 - offset
    denom = jnp.where(jnp.abs(d0 - d1) > 1e-12, d0 - d1, 1.0)
    cut = p0 + (d0 / denom) * (p1 - p0)
    q0 = jnp.where(d0 <= 0, p0, cut)
    q1 = jnp.where(d1 <= 0, p1, cut)
    return q0, q1, (d0 <= 0) | (d1 <= 0)


def collide_polygons(verts_a, normals_a, valid_a, verts_b, normals_b, valid_b, margin):
    """Two convex polygons: SAT over both, reference face, incident edge clipped to the face's side planes.

    Args: world vertices (4, 2), normals (4, 2) and valid-edge masks (4,) of both; margin [m].
    Returns: normal (2, 2), point (2, 2), separation (2,), feature (2,), valid (2,) for the 2 points.
    """
    sep_a, edge_a = _max_separation(verts_a, normals_a, valid_a, verts_b)
    sep_b, edge_b = _max_separation(verts_b, normals_b, valid_b, verts_a)
    flip = sep_b > sep_a + _REFERENCE_FACE_TOLERANCE
    ref_verts = jnp.where(flip, verts_b, verts_a)
    ref_edge = jnp.where(flip, edge_b, edge_a)
    inc_verts = jnp.where(flip, verts_a, verts_b)
    inc_normals = jnp.where(flip, normals_a, normals_b)
    inc_valid = jnp.where(flip, valid_a, valid_b)
    normal = jnp.where(flip, normals_b[edge_b], normals_a[edge_a])

    inc_edge = jnp.argmin(jnp.where(inc_valid, inc_normals @ normal, jnp.inf))
    w0, w1 = inc_verts[inc_edge], inc_verts[(inc_edge + 1) % 4]
    v0, v1 = ref_verts[ref_edge], ref_verts[(ref_edge + 1) % 4]
    tangent = v1 - v0
    tangent = tangent / jnp.maximum(jnp.linalg.norm(tangent), 1e-12)
    q0, q1, ok0 = _clip_segment(w0, w1, -tangent, -(tangent @ v0))
    q0, q1, ok1 = _clip_segment(q0, q1, tangent, tangent @ v1)

    points = jnp.stack([q0, q1])
    separation = points @ normal - normal @ v0
    valid = ok0 & ok1 & (jnp.maximum(sep_a, sep_b) <= margin) & (separation <= margin)
    midpoint = points - 0.5 * separation[:, None] * normal
    normal_ab = jnp.where(flip, -normal, normal)
    feature = flip.astype(jnp.int32) * 64 + ref_edge * 16 + inc_edge * 4 + jnp.arange(2)
    return jnp.stack([normal_ab, normal_ab]), midpoint, separation, feature.astype(jnp.int32), valid


def collide_polygon_circle(verts, normals, valid_edges, center, radius, margin):
    """Polygon a and circle b: face or vertex Voronoi region; a centre inside the polygon gets depth r + d.

    Returns: normal (2,), point (2,), separation (), feature (), valid ().
    """
    face_dist = jnp.where(valid_edges, jnp.sum(normals * (center - verts), axis=-1), -jnp.inf)
    edge = jnp.argmax(face_dist)
    dist = face_dist[edge]
    v0, v1 = verts[edge], verts[(edge + 1) % 4]
    outside = dist > 1e-6
    at_v0 = outside & ((center - v0) @ (v1 - v0) <= 0)
    at_v1 = outside & ~at_v0 & ((center - v1) @ (v0 - v1) <= 0)
    corner = jnp.where(at_v0, v0, v1)
    offset = center - corner
    corner_dist = jnp.linalg.norm(offset)
    use_corner = (at_v0 | at_v1) & (corner_dist > 1e-9)
    normal = jnp.where(use_corner, offset / jnp.maximum(corner_dist, 1e-9), normals[edge])
    surface_dist = jnp.where(use_corner, corner_dist, dist)
    separation = surface_dist - radius
    point = center - normal * (radius + 0.5 * separation)
    feature = jnp.where(at_v0, 4 + edge, jnp.where(at_v1, 8 + (edge + 1) % 4, edge))
    return normal, point, separation, feature.astype(jnp.int32), separation <= margin


def collide_circles(center_a, radius_a, center_b, radius_b, margin):
    """Two circles. Returns: normal (2,), point (2,), separation (), feature (), valid ()."""
    offset = center_b - center_a
    dist = jnp.linalg.norm(offset)
    normal = jnp.where(dist > 1e-9, offset / jnp.maximum(dist, 1e-9), jnp.array([0.0, 1.0]))
    separation = dist - radius_a - radius_b
    point = center_a + normal * (radius_a + 0.5 * separation)
    return normal, point, separation, jnp.int32(0), separation <= margin


def speculative_margins(static: Static, bodies: Bodies, v3: jax.Array, distance: jax.Array, dt) -> jax.Array:
    """(num_pairs,) distance [m] within which a pair gets contact points: `distance` plus how far either
    body's surface can move this step (|v| + |omega| * extent) * dt, so fast bodies do not tunnel."""
    extent = jnp.maximum(jnp.linalg.norm(bodies.vertices, axis=-1).max(-1), bodies.radius)
    reach = (jnp.linalg.norm(v3[:, :2], axis=-1) + jnp.abs(v3[:, 2]) * extent) * dt
    table = pair_table(static)
    return distance + reach[table.a] + reach[table.b]


def collide(static: Static, bodies: Bodies, margin: jax.Array) -> Manifold:
    """Candidate contact points of every pair in the pair table, in the table's point order.

    margin: (num_pairs,) speculative distance of each pair [m] (see `speculative_margins`).
    """
    table = pair_table(static)
    verts, normals, valid_edges = world_polygons(static, bodies)
    parts = []
    if table.num_pp:
        a, b = table.a[: table.num_pp], table.b[: table.num_pp]
        out = jax.vmap(collide_polygons)(
            verts[a], normals[a], valid_edges[a], verts[b], normals[b], valid_edges[b], margin[: table.num_pp]
        )
        parts.append(jax.tree.map(lambda x: x.reshape((-1,) + x.shape[2:]), out))
    if table.num_pc:
        sl = slice(table.num_pp, table.num_pp + table.num_pc)
        a, b = table.a[sl], table.b[sl]
        parts.append(
            jax.vmap(collide_polygon_circle)(
                verts[a], normals[a], valid_edges[a], bodies.position[b], bodies.radius[b], margin[sl]
            )
        )
    if table.num_cc:
        sl = slice(table.num_pp + table.num_pc, None)
        a, b = table.a[sl], table.b[sl]
        parts.append(
            jax.vmap(collide_circles)(
                bodies.position[a], bodies.radius[a], bodies.position[b], bodies.radius[b], margin[sl]
            )
        )
    if not parts:
        m = 0
        return Manifold(
            normal=jnp.zeros((m, 2)),
            point=jnp.zeros((m, 2)),
            separation=jnp.zeros((m,)),
            feature=jnp.zeros((m,), jnp.int32),
            valid=jnp.zeros((m,), bool),
        )
    fields = [jnp.concatenate([p[i] for p in parts]) for i in range(5)]
    return Manifold(*fields)
