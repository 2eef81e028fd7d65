"""The host-side scene builder: normalisation, slots, and one clear error per invalid field."""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
import pytest

from engine import SIZES, Scene, SceneError

S = SIZES["s"]


def test_winding_is_normalised_and_centroid_is_the_area_centroid():
    """Clockwise and counter-clockwise input build the same body; a triangle's centre is its area centroid."""
    tri = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
    built = []
    for verts in (tri, tri[::-1]):
        scene = Scene()
        scene.add_polygon((1.0, 1.0), verts)
        built.append(scene.build_numpy(S).bodies)
    np.testing.assert_allclose(built[0].vertices, built[1].vertices, atol=1e-7)
    np.testing.assert_allclose(built[0].position[4], (1.0 + 1 / 3, 1.0 + 1 / 3), atol=1e-6)
    v = built[0].vertices[4, :3]
    signed_area = 0.5 * sum(v[i, 0] * v[(i + 1) % 3, 1] - v[(i + 1) % 3, 0] * v[i, 1] for i in range(3))
    assert signed_area == pytest.approx(0.5, abs=1e-6)  # [m^2]; positive: counter-clockwise


def test_slots_polygons_then_circles():
    scene = Scene()
    p = scene.add_box((1, 1), (0.2, 0.2))
    c0 = scene.add_circle((2, 1), 0.1)
    c1 = scene.add_circle((3, 1), 0.1)
    assert [scene.slot(r, S) for r in (p, c0, c1)] == [4, 5, 6]
    bodies = scene.build_numpy(S).bodies
    assert bodies.active.tolist() == [True] * 7
    assert bodies.fixed.tolist() == [True] * 4 + [False] * 3


def test_one_rule_numbers_the_body_slots_of_every_size():
    s, m = SIZES["s"], SIZES["m"]  # s: 5 polygon slots and 2 circles; m: 6 and 3
    kinds = [("arena", 0), ("arena", 3), ("polygon", 0), ("circle", 0), ("circle", 1)]
    assert [s.slot(kind, i) for kind, i in kinds] == [0, 3, 4, 5, 6]
    assert [m.slot("polygon", 1), m.slot("circle", 0)] == [5, 6]
    assert np.asarray(m.slot("circle", jnp.arange(3))).tolist() == [6, 7, 8]  # traced indices too
    with pytest.raises(ValueError, match="kind must be one of"):
        s.slot("joint", 0)


def test_joint_anchors_and_fixed_reference_angle():
    """Anchors are stored in each body's frame; a fixed joint's reference angle is the built relative angle."""
    scene = Scene()
    a = scene.add_box((1.0, 1.0), (0.4, 0.2), angle=math.pi / 2)
    b = scene.add_circle((1.0, 2.0), 0.1)
    scene.add_fixed_joint(a, b, anchor=(1.0, 1.5))
    joints = scene.build_numpy(S).joints
    np.testing.assert_allclose(joints.anchor_a[0], (0.5, 0.0), atol=1e-6)
    np.testing.assert_allclose(joints.anchor_b[0], (0.0, -0.5), atol=1e-6)
    assert joints.ref_angle[0] == pytest.approx(-math.pi / 2, abs=1e-6)  # [rad]


def _bad(build):
    scene = Scene()
    build(scene)
    with pytest.raises(SceneError) as info:
        scene.build_numpy(S)
    return str(info.value)


@pytest.mark.parametrize(
    ("build", "expected"),
    [
        (lambda s: s.add_polygon((1, 1), [(0, 0), (1, 0), (1, 1), (0.9, 0.2)]), "polygon 'polygon 0': vertices"),
        (lambda s: s.add_polygon((1, 1), [(0, 0), (1, 0), (2, 0)]), "degenerate"),
        (lambda s: s.add_polygon((1, 1), [(0, 0), (1, 0)]), "need 3 or 4"),
        (lambda s: s.add_box((1, float("nan")), (1, 1), name="crate"), "polygon 'crate': position: must be finite"),
        (lambda s: s.add_circle((1, 1), -0.1), "circle 'circle 0': radius"),
        (lambda s: s.add_circle((1, 1), 0.1, density=0.0), "density"),
        (lambda s: s.add_circle((1, 1), 0.1, role=7), "role"),
        (lambda s: s.add_circle((1, 1), 0.1, collision_mode=3), "collision_mode"),
        (lambda s: [s.add_box((1, 1), (0.1, 0.1)) for _ in range(2)], "scene: polygons: has 2 but the size holds 1"),
        (lambda s: [s.add_circle((1, 1), 0.1) for _ in range(3)], "circles: has 3"),
        (
            lambda s: s.add_revolute_joint(
                s.add_circle((1, 1), 0.1), s.add_circle((2, 1), 0.1), (1, 1), limits=(1, -1)
            ),
            "joint 'joint 0': limits",
        ),
    ],
)
def test_invalid_descriptions_name_entity_and_field(build, expected):
    assert expected in _bad(build)


def test_joint_to_missing_body():
    from engine import BodyRef

    def build(scene):
        a = scene.add_circle((1, 1), 0.1)
        scene.add_revolute_joint(a, BodyRef("circle", 5), (1, 1))

    assert _bad(build) == "joint 'joint 0': body_b: circle 5 does not exist"


def test_thruster_errors_and_too_many():
    def build(scene):
        a = scene.add_circle((1, 1), 0.1)
        scene.add_thruster(a, (1, 1), angle=float("inf"))

    assert "thruster 'thruster 0': angle: must be finite" in _bad(build)

    def two(scene):
        a = scene.add_circle((1, 1), 0.1)
        scene.add_thruster(a, (1, 1), 0.0)
        scene.add_thruster(a, (1, 1), 0.0)

    assert "thrusters: has 2 but the size holds 1" in _bad(two)
