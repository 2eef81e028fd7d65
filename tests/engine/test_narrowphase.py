"""Contact geometry of each pair kind against hand-worked values (tolerance 1e-5 m)."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from engine.geometry import edge_normals
from engine.narrowphase import collide_circles, collide_polygon_circle, collide_polygons

SQUARE = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]], np.float32)


def _poly(verts, offset=(0.0, 0.0)):
    verts = jnp.asarray(verts, jnp.float32)
    normals, valid = edge_normals(verts, 4)
    return verts + jnp.asarray(offset, jnp.float32), normals, valid


def test_box_on_box_gives_two_clipped_points():
    """A unit box resting 0.1 m into a wider box: 2 points at the overlap's x extent (clipped, not clamped),
    depth 0.1 each, normal from a (below) to b (above)."""
    wide = np.array([[-2, -0.5], [2, -0.5], [2, 0.5], [-2, 0.5]], np.float32)
    normal, point, sep, _, valid = collide_polygons(*_poly(wide), *_poly(SQUARE, (0.3, 0.9)), jnp.float32(0.02))
    assert valid.all()
    np.testing.assert_allclose(normal, [[0, 1], [0, 1]], atol=1e-6)
    np.testing.assert_allclose(sep, [-0.1, -0.1], atol=1e-5)
    np.testing.assert_allclose(np.sort(np.asarray(point[:, 0])), [-0.2, 0.8], atol=1e-5)
    np.testing.assert_allclose(point[:, 1], [0.45, 0.45], atol=1e-5)


def test_box_overhanging_an_edge_clips_to_the_reference_face():
    """A box half off the end of a platform: the outer point is clipped to the platform's end (x = 1)."""
    platform = np.array([[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]], np.float32)
    _, point, sep, _, valid = collide_polygons(*_poly(platform), *_poly(SQUARE, (1.0, 0.95)), jnp.float32(0.02))
    assert valid.all()
    np.testing.assert_allclose(np.sort(np.asarray(point[:, 0])), [0.5, 1.0], atol=1e-5)
    np.testing.assert_allclose(sep, [-0.05, -0.05], atol=1e-5)


def test_separated_polygons_have_no_contact_beyond_margin():
    out = collide_polygons(*_poly(SQUARE), *_poly(SQUARE, (1.1, 0.0)), jnp.float32(0.05))
    assert not out[4].any()
    out = collide_polygons(*_poly(SQUARE), *_poly(SQUARE, (1.03, 0.0)), jnp.float32(0.05))
    assert out[4].all()
    np.testing.assert_allclose(out[2], [0.03, 0.03], atol=1e-5)


def test_circle_centre_inside_polygon_has_depth_r_plus_d():
    """Circle of radius 0.2 with its centre 0.1 inside the top face: separation -(0.2 + 0.1) (reference: -0.2)."""
    normal, point, sep, _, valid = collide_polygon_circle(*_poly(SQUARE), jnp.array([0.0, 0.4]), 0.2, 0.02)
    assert valid
    np.testing.assert_allclose(normal, [0, 1], atol=1e-6)
    assert abs(float(sep) + 0.3) < 1e-5
    np.testing.assert_allclose(point, [0.0, 0.4 - 0.2 + 0.15], atol=1e-5)


def test_circle_near_corner_uses_the_vertex_region():
    centre = jnp.array([0.6, 0.6])
    normal, _, sep, _, valid = collide_polygon_circle(*_poly(SQUARE), centre, 0.2, 0.02)
    d = np.hypot(0.1, 0.1)
    assert valid
    np.testing.assert_allclose(normal, [1 / np.sqrt(2), 1 / np.sqrt(2)], atol=1e-5)
    assert abs(float(sep) - (d - 0.2)) < 1e-5


def test_circle_circle():
    normal, point, sep, _, valid = collide_circles(jnp.array([0.0, 0.0]), 0.5, jnp.array([0.0, 0.8]), 0.4, 0.02)
    assert valid
    np.testing.assert_allclose(normal, [0, 1], atol=1e-6)
    assert abs(float(sep) + 0.1) < 1e-5
    np.testing.assert_allclose(point, [0, 0.45], atol=1e-5)
