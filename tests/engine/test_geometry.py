"""Mass properties against closed forms (tolerance 1e-5 relative, with float32 floors: 1e-6 kg, 1e-7 kg m^2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine import SIZES, Scene
from engine.geometry import mass_properties

S = SIZES["s"]


def _inverse(scene):
    bodies = scene.build_numpy(S).bodies
    return mass_properties(bodies, S.num_polygons, np)


def test_box_circle_triangle_mass_and_inertia():
    scene = Scene()
    scene.add_box((1, 1), size=(0.6, 0.4), density=2.0)
    scene.add_circle((2, 2), radius=0.3, density=1.5)
    inv_mass, inv_inertia = _inverse(scene)
    m_box = 2.0 * 0.24
    assert 1 / inv_mass[4] == pytest.approx(m_box, rel=1e-5, abs=1e-6)  # [kg]
    assert 1 / inv_inertia[4] == pytest.approx(m_box * (0.36 + 0.16) / 12, rel=1e-5, abs=1e-7)  # [kg m^2]
    m_circle = 1.5 * math.pi * 0.09
    assert 1 / inv_mass[5] == pytest.approx(m_circle, rel=1e-5, abs=1e-6)  # [kg]
    # m r^2 / 2 (reference: half of it)
    assert 1 / inv_inertia[5] == pytest.approx(m_circle * 0.09 / 2, rel=1e-5, abs=1e-7)  # [kg m^2]

    tri = Scene()
    tri.add_polygon((0, 0), [(0, 0), (1, 0), (0, 1)], density=1.0)
    inv_mass, inv_inertia = _inverse(tri)
    # right triangle with legs 1: area 1/2, polar moment about the centroid = m (a^2 + b^2) / 18
    assert 1 / inv_mass[4] == pytest.approx(0.5, rel=1e-5, abs=1e-6)  # [kg]
    assert 1 / inv_inertia[4] == pytest.approx(0.5 * 2 / 18, rel=1e-5, abs=1e-7)  # [kg m^2]


def test_fixed_inactive_and_arena_have_infinite_mass():
    scene = Scene()
    scene.add_box((1, 1), size=(0.6, 0.4), fixed=True)
    scene.add_circle((2, 2), radius=0.3, active=False)
    inv_mass, inv_inertia = _inverse(scene)
    assert np.all(inv_mass[:6] == 0) and np.all(inv_inertia[:6] == 0)
