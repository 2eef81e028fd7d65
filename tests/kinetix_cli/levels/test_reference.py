"""Reference-format levels: the 74 hand-made levels of the paper convert, load, step and render; the conversion
keeps what it should and notes what it cannot. The levels come from `make reference-levels` (`make test` runs it).
"""

from __future__ import annotations

import copy
import functools
import json
import math
from pathlib import Path

import jax
import numpy as np
import pytest

from engine import SIZES, polygon_area_centroid
from helpers.paths import REFERENCE_LEVELS
from kinetix_cli.env.actions import sample_action
from kinetix_cli.env.environment import EnvParams, KinetixEnv, is_finite
from kinetix_cli.env.episode import run_episode
from kinetix_cli.env.level import stack_levels
from kinetix_cli.errors import LevelError
from kinetix_cli.levels.files import ConversionWarning, import_reference_file, load_level
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.reference import convert_reference_level

REFERENCE = REFERENCE_LEVELS
COUNTS = {"s": 10, "m": 24, "l": 40}
# The only notes on the 74 levels: two joints whose anchors start apart (the reference pulls them together).
EXPECTED_NOTES = {
    "l/gears.json": ["joint 4: b_relative_pos"],
    "m/arm_up.json": ["joint 1: b_relative_pos"],
}


def reference_files(size: str) -> list[Path]:
    if not (REFERENCE / ".fetched").exists():
        pytest.fail(f"{REFERENCE} is missing: run `make reference-levels` (make test does)")
    return sorted((REFERENCE / size).glob("*.json"))


def read(name: str) -> dict:
    return json.loads((REFERENCE / name).read_text())


@functools.cache
def converted(size: str) -> tuple[list[Path], list]:
    """Every reference level of a size, converted and parsed: (files, specs)."""
    files = reference_files(size)
    specs = []
    for path in files:
        data, notes = convert_reference_level(json.loads(path.read_text()), str(path))
        key = f"{size}/{path.name}"
        assert [f"{n.entity}: {n.field}" for n in notes] == EXPECTED_NOTES.get(key, []), key
        specs.append(parse_level(data, str(path)))
    return files, specs


@pytest.mark.parametrize("size", ["s", "m", "l"])
def test_all_reference_levels_convert_at_their_size(size):
    files, specs = converted(size)
    assert len(files) == COUNTS[size]
    for path, spec in zip(files, specs, strict=True):
        assert spec.size == size, path
        level = spec.build()
        roles = np.asarray(level.physics.bodies.role)[np.asarray(level.physics.bodies.active)]
        assert 1 in roles and 2 in roles, f"{path}: no green or no blue"


@functools.partial(jax.jit, static_argnums=0)
def _random_steps(env: KinetixEnv, levels, key):
    """256 environment steps of each level under uniformly random multi-discrete actions, without resets;
    returns (B,) bool: the physics stayed finite at every step."""

    def one(level, key):
        policy = lambda k, obs, t: sample_action("multi-discrete", k)  # noqa: E731
        _, trace = run_episode(env, EnvParams(), level, policy, key, 256, record=True)
        return jax.vmap(is_finite)(trace.physics).all()

    keys = jax.random.split(key, jax.tree.leaves(levels)[0].shape[0])
    return jax.vmap(one)(levels, keys)


@pytest.mark.parametrize(
    "size", ["s", pytest.param("m", marks=pytest.mark.slow), pytest.param("l", marks=pytest.mark.slow)]
)  # m and l: 12-14 s of compile each (make test-all)
def test_reference_levels_step_256_random_steps_without_nan(size):
    files, specs = converted(size)
    finite = np.asarray(
        _random_steps(KinetixEnv(SIZES[size]), stack_levels([s.build() for s in specs]), jax.random.key(0))
    )
    assert finite.all(), [str(p) for p, ok in zip(files, finite, strict=True) if not ok]


def test_reference_levels_render(tmp_path):
    from kinetix_cli.viz.render import render_level, save_png

    for size in ("s", "m", "l"):
        files, specs = converted(size)
        for path, spec in zip(files[:3], specs[:3], strict=True):
            save_png(render_level(spec.build(), scale=20, title=spec.name), tmp_path / f"{path.stem}.png")
    assert len(list(tmp_path.glob("*.png"))) == 9


def test_bodies_joints_and_thrusters_carry_over():
    """One-wheel car: positions, angles, role, motor binding and speed, thruster, gravity; polygons turn CCW."""
    ref = read("s/h2_one_wheel_car.json")
    level = parse_level(convert_reference_level(ref, "h2_one_wheel_car.json")[0]).build()
    bodies, joints = level.physics.bodies, level.physics.joints
    state = ref["env_state"]
    for k, shape in enumerate(state["polygon"] + state["circle"]):
        if k < 4 or not shape["active"]:
            continue
        np.testing.assert_allclose(bodies.position[k], [shape["position"]["0"], shape["position"]["1"]], atol=1e-5)
        assert math.isclose(float(bodies.angle[k]), shape["rotation"], abs_tol=1e-5)
        assert int(bodies.role[k]) == shape["role"]
        assert bool(bodies.fixed[k]) == (shape["inverse_mass"] == 0)
    ref_joint = state["joint"][0]
    assert (int(joints.body_a[0]), int(joints.body_b[0])) == (ref_joint["a_index"], ref_joint["b_index"])
    assert bool(joints.motor_on[0]) and int(level.bindings.motor[0]) == ref_joint["motor_binding"]
    assert math.isclose(float(joints.motor_speed[0]), ref_joint["motor_speed"], rel_tol=1e-6, abs_tol=1e-6)  # [rad/s]
    np.testing.assert_allclose(level.physics.gravity, [0.0, -9.81], atol=1e-6)
    area, _ = polygon_area_centroid(np.asarray(bodies.vertices[4]), np)
    assert area > 0


def test_revolute_limits_become_absolute():
    """The reference measures limits from the joint's `rotation`; ours are on angle_b - angle_a."""
    ref = read("l/grasp_easy.json")
    level = parse_level(convert_reference_level(ref, "grasp_easy.json")[0]).build()
    active = [j for j in ref["env_state"]["joint"] if j["active"]]
    limited = [k for k, j in enumerate(active) if j["motor_has_joint_limits"]]
    assert limited
    for k in limited:
        j = active[k]
        assert math.isclose(float(level.physics.joints.min_angle[k]), j["min_rotation"] + j["rotation"], abs_tol=1e-5)
        assert math.isclose(float(level.physics.joints.max_angle[k]), j["max_rotation"] + j["rotation"], abs_tol=1e-5)


def test_off_centre_polygon_is_recentred_with_its_anchors():
    """A polygon whose vertices are not centred on its position moves to its centroid; anchors stay in place."""
    ref = copy.deepcopy(read("s/h2_one_wheel_car.json"))
    chassis = ref["env_state"]["polygon"][4]
    for v in chassis["vertices"].values():
        v["0"] += 0.1
    joint = ref["env_state"]["joint"][0]
    world_before = np.array([chassis["position"]["0"], chassis["position"]["1"]])
    level = parse_level(convert_reference_level(ref, "shifted")[0]).build()
    bodies, joints = level.physics.bodies, level.physics.joints
    c, s = math.cos(chassis["rotation"]), math.sin(chassis["rotation"])
    np.testing.assert_allclose(bodies.position[4], world_before + [0.1 * c, 0.1 * s], atol=1e-5)
    a_rel = np.array([joint["a_relative_pos"]["0"], joint["a_relative_pos"]["1"]])
    np.testing.assert_allclose(joints.anchor_a[0], a_rel - [0.1, 0.0], atol=1e-5)


def test_what_cannot_be_carried_over_is_noted():
    ref = copy.deepcopy(read("s/h0_weak_thrust.json"))
    ref["env_params"]["max_timesteps"] = 512
    ref["env_params"]["dt"] = 0.01
    ref["static_env_params"]["num_solver_iterations"] = 4
    ref["env_state"]["polygon"][1]["position"]["0"] = -1.0  # a moved left wall
    data, notes = convert_reference_level(ref, "edited.json")
    fields = {(n.entity, n.field) for n in notes}
    assert fields == {
        ("env_params", "max_timesteps"),
        ("static_env_params", "num_solver_iterations"),
        ("polygon 1 (arena)", "position/vertices"),
    }
    assert data["params"] == {"dt": 0.01}  # engine constants are carried as parameter overrides


@pytest.mark.parametrize(
    ("edit", "field"),
    [
        (lambda d: d["env_state"].pop("polygon"), "env_state.polygon: missing"),
        (lambda d: d["env_state"]["circle"][0].update(radius="big"), "env_state.circle[0].radius"),
        (lambda d: d["env_state"]["polygon"][4].update(n_vertices=5), "env_state.polygon[4].n_vertices"),
        (lambda d: d["env_state"]["circle"][0].update(role=7), "env_state.circle[0].role"),
        (lambda d: d["env_state"]["joint"][0].update(motor_binding=9), "env_state.joint[0].motor_binding"),
    ],
)
def test_malformed_reference_levels_name_the_field(edit, field):
    ref = copy.deepcopy(read("s/h2_one_wheel_car.json"))
    edit(ref)
    with pytest.raises(LevelError, match=f"^bad.json: {field}".replace("[", r"\[").replace("]", r"\]")):
        convert_reference_level(ref, "bad.json")


def test_load_level_converts_reference_files_and_warns(tmp_path):
    """Commands that take level files read reference files directly; notes arrive as ConversionWarnings."""
    plain = load_level(REFERENCE / "s" / "h2_one_wheel_car.json")
    assert plain.size == "s" and len(plain.scene.joints) == 1
    with pytest.warns(ConversionWarning, match=r"arm_up.json: joint 1: b_relative_pos"):
        load_level(REFERENCE / "m" / "arm_up.json")


def test_import_writes_a_level_file_that_loads_the_same(tmp_path):
    source = REFERENCE / "m" / "h5_angry_birds.json"
    out = tmp_path / "out" / "angry.json"
    assert import_reference_file(source, out) == []
    written = json.loads(out.read_text())
    assert written["format"] == "kinetix-level/1" and written["size"] == "m"
    a, b = load_level(out).build(), load_level(source).build()
    for x, y in zip(jax.tree.leaves(a), jax.tree.leaves(b), strict=True):
        np.testing.assert_array_equal(x, y)
    with pytest.raises(LevelError, match="need no import"):
        import_reference_file(out, tmp_path / "again.json")
