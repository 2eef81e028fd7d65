"""Level files: parsing, validation messages naming file/entity/field, building into sizes."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest

from engine import SIZES
from helpers.levels import CAR
from kinetix_cli.errors import LevelError
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.format import format_level_json
from kinetix_cli.levels.parse import parse_level


def edited(path: str, value):
    """CAR with one field replaced; `path` is a dotted path with list indices."""
    data = copy.deepcopy(CAR)
    *parents, last = path.split(".")
    node = data
    for key in parents:
        node = node[int(key)] if key.isdigit() else node[key]
    if value is _DELETE:
        del node[int(last) if last.isdigit() else last]
    else:
        node[int(last) if last.isdigit() else last] = value
    return data


_DELETE = object()


def test_builds_bodies_bindings_and_materials():
    spec = parse_level(CAR)
    level = spec.build()
    b = level.physics.bodies
    assert spec.default_static() == SIZES["s"]
    np.testing.assert_allclose(b.position[4], [1.0, 0.8], atol=1e-6)  # first non-arena polygon slot
    assert b.role[4] == 1 and b.role[6] == 2 and bool(b.fixed[6])
    assert int(level.bindings.motor[0]) == 2 and not bool(level.bindings.motor_auto[0])
    assert int(level.bindings.thruster[0]) == 1
    np.testing.assert_allclose(level.physics.joints.motor_speed[0], 0.5, atol=1e-6)  # [rad/s]
    np.testing.assert_allclose(level.physics.thrusters.angle[0], np.pi / 2, atol=1e-6)


def test_pads_into_larger_sizes():
    spec = parse_level(CAR)
    for name in ("m", "l"):
        level = spec.build(SIZES[name])
        assert level.physics.bodies.active.sum() == 4 + 3
        assert level.physics.joints.active.sum() == 1


def test_auto_motor_arena_anchor_and_overrides():
    data = edited("joints.0.motor", {"binding": "auto"})
    data["joints"][0]["b"] = "floor"
    data["arena"] = {"floor": {"role": "red"}, "ceiling": {"enabled": False}}
    data["params"] = {"base_motor_power": 600}
    spec = parse_level(data)
    level = spec.build()
    assert bool(level.bindings.motor_auto[0])
    assert int(level.physics.joints.body_b[0]) == 0
    assert level.physics.bodies.role[0] == 3 and not level.physics.bodies.active[3]
    assert spec.engine_params().base_motor_power == 600


@pytest.mark.parametrize(
    "path, value, message",
    [
        (
            "format",
            "kinetix-level/2",
            'level: format: this kinetix reads "kinetix-level/1" only, got "kinetix-level/2"',
        ),
        ("bodies.0.role", "purple", "bodies[0] 'chassis': role: must be one of"),
        ("bodies.1.radius", -0.2, "bodies[1] 'wheel': radius: must be > 0"),
        ("bodies.1.radius", _DELETE, "bodies[1] 'wheel': radius: missing"),
        ("bodies.0.colour", "red", "bodies[0] 'chassis': colour: unknown key"),
        ("bodies.2.name", "chassis", "bodies[2] 'chassis': name: already used"),
        ("bodies.0.position", [1.0], "bodies[0] 'chassis': position: must be [x, y]"),
        ("bodies.0.density", float("nan"), "bodies[0] 'chassis': density: must be a finite number"),
        ("joints.0.b", "nowhere", "joints[0]: b: no body named"),
        ("joints.0.motor.binding", 4, "joints[0].motor: binding: must be one of"),
        ("thrusters.0.binding", 2, "thrusters[0]: binding: must be one of"),
        ("size", "xl", "level: size: must be one of"),
    ],
)
def test_errors_name_file_entity_and_field(path, value, message):
    with pytest.raises(LevelError) as info:
        parse_level(edited(path, value), "levels/car.json")
    assert str(info.value).startswith("levels/car.json: ")
    assert message in str(info.value)


def test_geometry_errors_come_from_the_scene_builder():
    data = edited(
        "bodies.0", {"name": "chassis", "shape": "polygon", "position": [1, 1], "vertices": [[0, 0], [1, 0], [2, 0]]}
    )
    with pytest.raises(LevelError, match=r"levels/x.json: polygon 'chassis': vertices: degenerate"):
        parse_level(data, "levels/x.json")


def test_too_big_for_its_size():
    data = copy.deepcopy(CAR)
    data["bodies"].append({"name": "box2", "shape": "box", "size": [0.2, 0.2], "position": [3, 1]})
    with pytest.raises(LevelError, match="level: size: too big for size s: polygons: has 2 but the size holds 1"):
        parse_level(data, "x.json")
    del data["size"]
    assert parse_level(data).default_static() == SIZES["m"]


def test_file_errors(tmp_path):
    with pytest.raises(LevelError, match="no such file"):
        load_level(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": ')
    with pytest.raises(LevelError, match=r"bad.json: not valid JSON"):
        load_level(bad)


def test_formatted_json_round_trips(tmp_path):
    data = dict(CAR, solution={"actions": [[[1, 0, 0, 0, 0, 0], 16], [[0, 0, 0, 0, 1, 0], 4]]})
    text = format_level_json(data)
    assert json.loads(text) == data
    assert '"solution": {"actions": [[[1, 0, 0, 0, 0, 0], 16], [[0, 0, 0, 0, 1, 0], 4]]}' in text
    path = tmp_path / "car.json"
    path.write_text(text)
    assert load_level(path).name == "car"
