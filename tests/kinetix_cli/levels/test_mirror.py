"""`kinetix levels mirror`: a mirrored level file is a valid level whose mirrored solution solves it, mirroring twice
gives the level back, a mirrored set holds the mirror of each level, and bad input is one line."""

from __future__ import annotations

import json

import jax
import numpy as np

from engine import SIZES
from helpers.cli import kinetix
from helpers.levels import CAR
from helpers.levelsets import small_levelset
from helpers.paths import LEVELS
from kinetix_cli.env.level import level_count
from kinetix_cli.env.mirror import mirror_level
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.levelset import level_at, load_levelset
from kinetix_cli.levels.mirror import mirrored_level_data
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.solution import SOLUTION_SETTINGS, check_level, decode_solution

S_LEVELS = sorted((LEVELS / "s").glob("*.json"))


def test_the_mirror_of_every_s_level_is_solved_by_its_mirrored_solution_and_mirrors_back(capsys, tmp_path):
    """Our 10 s levels. (Of all 60, 58 mirrored solutions solve; inchworm-crawl (m) and maze-thruster-ball (l), whose
    solutions are near the edge (maze: 254 of 256 steps), do not: the contact solver's sequential order is not
    mirror-symmetric, so a mirror image drifts by ~1e-4 m a second.)"""
    result = kinetix(capsys, "levels", "mirror", "s", "-o", tmp_path / "out")
    assert result.code == 0 and "wrote 10 mirrored level files" in result.out
    for source in S_LEVELS:
        spec = load_level(tmp_path / "out" / "s" / source.name)
        assert spec.name.endswith("(mirrored)") and spec.size == "s"
        outcome = check_level(spec)
        assert bool(outcome["solution"].solved[0]), source.name
        assert not bool(outcome["noop"].solved[0]), source.name
        back = parse_level(mirrored_level_data(spec)).build(SIZES["s"])
        original = load_level(source).build(SIZES["s"])
        for a, b in zip(jax.tree.leaves(original), jax.tree.leaves(back), strict=True):
            np.testing.assert_allclose(np.asarray(b), np.asarray(a), rtol=0, atol=1e-5, err_msg=source.name)  # [m, rad]
        solution = decode_solution(load_level(source).solution, "", SOLUTION_SETTINGS.max_steps)
        twice = decode_solution(mirrored_level_data(spec)["solution"], "", SOLUTION_SETTINGS.max_steps)
        np.testing.assert_array_equal(twice, solution)


def test_an_auto_motor_is_written_with_a_negative_speed(tmp_path):
    car = CAR | {"joints": [CAR["joints"][0] | {"motor": {"binding": "auto", "speed": 0.5}}]}
    data = mirrored_level_data(parse_level(car))
    assert data["joints"][0]["motor"] == {"binding": "auto", "speed": -0.5}
    assert float(parse_level(data).build().physics.joints.motor_speed[0]) == -0.5


def test_a_mirrored_set_holds_the_mirror_of_each_level_and_names_its_source(capsys, tmp_path):
    source = tmp_path / "set"
    manifest = small_levelset(source)
    result = kinetix(capsys, "levels", "mirror", source, "-o", tmp_path / "mirrored")
    assert result.code == 0, result.err
    mirrored = load_levelset(tmp_path / "mirrored")
    original = load_levelset(source)
    assert level_count(mirrored.levels) == manifest["count"] == 6
    assert mirrored.manifest["settings"]["mirror_of"]["seed"] == manifest["seed"]
    assert mirrored.manifest["settings"]["mirror_of"]["shards"] == [s["sha256"] for s in manifest["shards"]]
    for i in range(6):
        expected = jax.device_get(mirror_level(level_at(original, i)))
        for a, b in zip(jax.tree.leaves(expected), jax.tree.leaves(level_at(mirrored, i)), strict=True):
            np.testing.assert_array_equal(np.asarray(b), np.asarray(a))
    again = kinetix(capsys, "levels", "mirror", source, "-o", tmp_path / "mirrored")  # finished: nothing rewritten
    assert again.code == 0 and load_levelset(tmp_path / "mirrored").manifest == mirrored.manifest


def test_one_file_to_a_file_and_bad_input_in_one_line(capsys, tmp_path):
    result = kinetix(capsys, "levels", "mirror", S_LEVELS[0], "-o", tmp_path / "one.json")
    assert result.code == 0 and json.loads((tmp_path / "one.json").read_text())["format"] == "kinetix-level/1"
    line = kinetix(capsys, "levels", "mirror", tmp_path / "nowhere", "-o", tmp_path / "x").error_line
    assert "nowhere: no such file or folder" in line
    line = kinetix(capsys, "levels", "mirror", S_LEVELS[0], S_LEVELS[0], "-o", tmp_path / "twice").error_line
    assert "two levels would be written to" in line and not (tmp_path / "twice").exists()
