"""Mass properties and polygon geometry, written once for numpy (host builder) and jax.numpy (device).

Functions take `xp`, the array module, so the builder and the step share one definition.
"""

from __future__ import annotations

from types import ModuleType

import jax.numpy as jnp


def cross(a, b):
    """z of the 2D cross product: (..., 2) x (..., 2) -> (...)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def cross_scalar_vector(s, v, xp: ModuleType = jnp):
    """s x v for a scalar (...,) and a vector (..., 2): the velocity of a point at v under spin s."""
    return xp.stack([-s * v[..., 1], s * v[..., 0]], axis=-1)


def rotate(v, angle, xp: ModuleType = jnp):
    """Rotate (..., 2) vectors by (...) angles [rad] counter-clockwise."""
    c, s = xp.cos(angle), xp.sin(angle)
    return xp.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def polygon_area_centroid(vertices, xp: ModuleType = jnp):
    """Signed area [m^2] (positive when counter-clockwise) and area centroid (..., 2) [m].

    `vertices` is (..., 4, 2) in the padded layout (a triangle repeats vertex 0 in slot 3), so the
    closing edges contribute zero and one fixed loop serves triangles and quads.
    """
    nxt = xp.roll(vertices, -1, axis=-2)
    c = cross(vertices, nxt)
    area = 0.5 * c.sum(-1)
    safe = xp.where(xp.abs(area) > 1e-12, area, 1.0)
    centroid = ((vertices + nxt) * c[..., None]).sum(-2) / (6.0 * safe[..., None])
    return area, centroid


def polygon_unit_inertia(vertices, xp: ModuleType = jnp):
    """Polar moment of area about the origin for unit density [m^4]; vertices as in `polygon_area_centroid`."""
    nxt = xp.roll(vertices, -1, axis=-2)
    c = cross(vertices, nxt)
    terms = (vertices * vertices).sum(-1) + (vertices * nxt).sum(-1) + (nxt * nxt).sum(-1)
    return (c * terms).sum(-1) / 12.0


def mass_properties(bodies, num_polygons: int, xp: ModuleType = jnp):
    """Inverse mass [1/kg] and inverse rotational inertia about the centre of mass [1/(kg m^2)], each (N,).

    Polygons use the true area and polar moment (vertices are stored about the area centroid); circles
    m = rho pi r^2 and I = m r^2 / 2. Fixed and inactive bodies get zero (infinite mass).
    """
    n = bodies.radius.shape[-1]
    is_circle = xp.arange(n) >= num_polygons
    area_poly, _ = polygon_area_centroid(bodies.vertices, xp)
    area = xp.where(is_circle, xp.pi * bodies.radius**2, area_poly)
    unit_inertia = xp.where(is_circle, 0.5 * xp.pi * bodies.radius**4, polygon_unit_inertia(bodies.vertices, xp))
    mass = bodies.density * area
    inertia = bodies.density * unit_inertia
    movable = bodies.active & ~bodies.fixed & (mass > 0) & (inertia > 0)
    inv_mass = xp.where(movable, 1.0 / xp.where(movable, mass, 1.0), 0.0)
    inv_inertia = xp.where(movable, 1.0 / xp.where(movable, inertia, 1.0), 0.0)
    return inv_mass.astype(xp.float32), inv_inertia.astype(xp.float32)


def edge_normals(vertices, num_vertices, xp: ModuleType = jnp):
    """Outward unit normals (..., 4, 2) of counter-clockwise padded polygons and a (..., 4) valid-edge mask."""
    edges = xp.roll(vertices, -1, axis=-2) - vertices
    length = xp.sqrt((edges * edges).sum(-1))
    normals = xp.stack([edges[..., 1], -edges[..., 0]], axis=-1) / xp.maximum(length, 1e-12)[..., None]
    valid = xp.arange(4) < xp.asarray(num_vertices)[..., None]
    return normals, valid
