"""Level export: every shipped level and random full scenes survive export -> parse -> build unchanged."""

from __future__ import annotations

import json

import jax
import numpy as np
import pytest

from engine import SIZES, Scene
from helpers.paths import LEVELS
from kinetix_cli.bench.env import random_levels
from kinetix_cli.env.level import Bindings, Level, make_level
from kinetix_cli.levels.export import export_level
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.format import format_level_json
from kinetix_cli.levels.parse import parse_level

SHIPPED = sorted(LEVELS.glob("[sml]/*.json"))


def round_trip(level: Level, static, name: str = "exported") -> Level:
    """Export `level`, write and read the JSON text, parse and build it at `static`."""
    data = json.loads(format_level_json(export_level(level, static, name=name, description="round trip")))
    return parse_level(data, f"<{name}>").build(static)


def assert_levels_equal(got: Level, want: Level) -> None:
    """Every leaf equal: floats to 1e-5 (float32 rounding, polygon re-centring), ints and bools exactly."""
    got_leaves = jax.tree_util.tree_leaves_with_path(got)
    want_leaves = jax.tree.leaves(want)
    assert len(got_leaves) == len(want_leaves)
    for (path, g), w in zip(got_leaves, want_leaves, strict=True):
        g, w = np.asarray(g), np.asarray(w)
        where = jax.tree_util.keystr(path)
        assert g.shape == w.shape and g.dtype == w.dtype, where
        if np.issubdtype(w.dtype, np.floating):
            np.testing.assert_allclose(g, w, rtol=0, atol=1e-5, err_msg=where)
        else:
            np.testing.assert_array_equal(g, w, err_msg=where)


def canonical_bindings(level: Level) -> Level:
    """`level` with the bindings that have no effect set as the format builds them: a joint without a motor
    or with an auto motor has motor binding 0 (the format writes only "auto"), and motor_auto is False on a
    joint without a motor, and an empty thruster slot has binding 0. These are the only fields of a random
    level that cannot round-trip (they have no effect on the physics or the actions)."""
    joints, thrusters = level.physics.joints, level.physics.thrusters
    motor = np.asarray(joints.motor_on) & np.asarray(joints.active)
    auto = np.asarray(level.bindings.motor_auto) & motor
    binding = np.where(motor & ~auto, np.asarray(level.bindings.motor), 0).astype(np.int32)
    thruster = np.where(np.asarray(thrusters.active), np.asarray(level.bindings.thruster), 0).astype(np.int32)
    return level.replace(bindings=Bindings(binding, auto, thruster))


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_shipped_levels_round_trip(path):
    spec = load_level(path)
    static = spec.default_static()
    level = spec.build(static)
    assert_levels_equal(round_trip(level, static, spec.name), level)


def test_random_levels_round_trip():
    static = SIZES["m"]
    batch = random_levels(static, 16, 0)
    for i in range(16):
        level = jax.tree.map(lambda x, i=i: np.asarray(x)[i], batch)
        assert_levels_equal(round_trip(level, static, f"random-{i}"), canonical_bindings(level))


def test_writes_readable_defaults_and_names():
    spec = load_level(LEVELS / "m/golf-swing.json")
    data = export_level(spec.build(), SIZES["m"], name="golf", description="loft the ball")
    assert data["size"] == "m" and "gravity" not in data
    assert data["arena"] == {"floor": {"role": "red"}}
    club = data["bodies"][0]
    assert club == {
        "name": "polygon-0",
        "shape": "polygon",
        "position": [1.0, 1.84],
        "vertices": [[-0.05, -0.41], [0.05, -0.41], [0.05, 0.41], [-0.05, 0.41]],
        "density": 4.0,
    }
    assert [b["name"] for b in data["bodies"]] == ["polygon-0", "polygon-1", "circle-0", "circle-1", "circle-2"]
    assert data["joints"] == [
        {"a": "ceiling", "b": "polygon-0", "anchor": [1.0, 2.25], "motor": {"binding": 0, "speed": 1.2, "power": 3.0}}
    ]


def test_inactive_slots_are_left_out_and_disabled_arena_kept():
    static = SIZES["l"]
    scene = Scene(gravity=(0.0, -5.0))
    scene.arena[3].active = False
    box = scene.add_box((2.0, 1.0), (0.5, 0.5), angle=0.3, role=1, angular_velocity=1.0)
    scene.add_circle((3.0, 1.0), 0.2, collision_mode=2)
    scene.add_revolute_joint(box, scene.add_circle((2.0, 2.0), 0.1), (2.0, 1.5), limits=(-0.5, 0.5))
    scene.add_thruster(box, (2.25, 1.0), angle=1.0, power=2.0)
    bindings = Bindings(np.full(6, 3, np.int32), np.zeros(6, bool), np.ones(2, np.int32))
    level = make_level(scene.build_numpy(static), bindings)
    data = export_level(level, static, name="small", description="")
    assert data["gravity"] == [0.0, -5.0] and data["arena"] == {"ceiling": {"enabled": False}}
    assert len(data["bodies"]) == 3 and len(data["joints"]) == 1 and len(data["thrusters"]) == 1
    assert data["thrusters"][0]["binding"] == 1 and "motor" not in data["joints"][0]
    assert data["joints"][0]["limits_deg"] == pytest.approx([-28.64789, 28.64789], abs=1e-4)
    assert_levels_equal(round_trip(level, static), canonical_bindings(level))


def test_refuses_what_the_format_cannot_hold():
    static = SIZES["s"]
    scene = Scene()
    scene.add_circle((2.0, 1.0), 0.2)
    physics = scene.build_numpy(static)
    physics.bodies.angle[static.num_polygons] = 0.5
    bindings = Bindings(np.zeros(1, np.int32), np.zeros(1, bool), np.zeros(1, np.int32))
    turned = export_level(make_level(physics, bindings), static, name="turned", description="")
    assert turned["bodies"][0]["angle_deg"] == pytest.approx(np.degrees(0.5), abs=1e-5)  # [deg]; float32 ulp 3e-6
    built = parse_level(turned).build(static).physics.bodies
    assert built.angle[static.num_polygons] == pytest.approx(0.5, abs=1e-6)  # [rad]
    with pytest.raises(ValueError, match="slots"):
        export_level(make_level(physics, bindings), SIZES["m"], name="wrong size", description="")


def test_engine_constants_round_trip_as_params_overrides():
    """A level's engine constants go out as `params` where they differ from the defaults, and come back."""
    data = {
        "format": "kinetix-level/1",
        "size": "s",
        "bodies": [{"name": "g", "shape": "circle", "radius": 0.2, "position": [1.0, 1.0], "role": "green"}],
        "params": {"dt": 0.02, "base_thruster_power": 7.5},
    }
    level = parse_level(data).build()
    exported = export_level(level, SIZES["s"], name="params", description="")
    assert exported["params"] == {"dt": 0.02, "base_thruster_power": 7.5}
    assert_levels_equal(round_trip(level, SIZES["s"]), level)
    default = parse_level(data | {"params": {}}).build()
    assert "params" not in export_level(default, SIZES["s"], name="default", description="")
