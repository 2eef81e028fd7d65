"""`kinetix rollout` with several levels: each played on its own with the same policy and seed (its line as if it
were alone), one GIF of them in a grid; one level keeps its single-episode GIF; bad input is one line."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from PIL import Image
from typer.testing import CliRunner

from helpers.cli import kinetix
from helpers.runs import EVAL_LEVEL
from kinetix_cli.cli.app import app
from kinetix_cli.viz.render import frame_size

runner = CliRunner()
PAD, AIM, UPHILL = "levels/s/pad-to-pad.json", "levels/s/aim-then-fire.json", "levels/m/uphill-wheel.json"
SCALE = 20


def _outcomes(output: str) -> list[str]:
    """The per-level outcome lines."""
    return [line for line in output.splitlines() if ": policy " in line]


def test_two_levels_make_one_gif_of_two_tiles(tmp_path):
    gif = tmp_path / "two.gif"
    args = ["rollout", PAD, AIM, "--policy", "solution", "--scale", str(SCALE), "-o", str(gif)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    lines = _outcomes(result.output)
    assert len(lines) == 2 and lines[0].startswith("pad to pad: policy solution: solved after")
    assert "solved 2 of 2 levels" in result.output
    steps = [int(re.search(r"after (\d+) steps", line).group(1)) for line in lines]
    frames = int(re.search(r"wrote .* \((\d+) frames\)", result.output).group(1))
    assert frames == max(steps) + 1 + 30  # the longer episode's frames, then a second held (solutions: 30 steps/s)
    w, h = frame_size(SCALE)
    with Image.open(gif) as image:
        assert image.format == "GIF" and image.width == 2 * w + 3 * 6 and image.height > h + 2 * 6


def test_one_level_keeps_its_single_episode_gif(tmp_path):
    gif = tmp_path / "one.gif"
    result = runner.invoke(app, ["rollout", PAD, "--policy", "solution", "--scale", str(SCALE), "-o", str(gif)])
    assert result.exit_code == 0, result.output
    steps = int(re.search(r"solved after (\d+) steps", result.output).group(1))
    assert f"({steps + 1} frames)" in result.output and "levels" not in result.output
    with Image.open(gif) as image:
        assert image.size == frame_size(SCALE)


@pytest.mark.slow  # ~40 s: compiles a policy episode at size m; make test keeps the grid (two s tiles, above)
def test_a_trained_policy_plays_levels_of_two_sizes_in_one_gif(tmp_path, tiny_run):
    # a trained policy (the suite's tiny run, whose update and rollouts other tests compile too) samples its actions:
    # the s level, second after an m level, plays with --seed 1's own key, as alone (its seed-0 line differs, so a key
    # derived per level would show)
    gif, policy = tmp_path / "mixed.gif", str(tiny_run)
    args = ["rollout", UPHILL, EVAL_LEVEL, "--policy", policy, "--seed", "1", "--columns", "1"]
    result = runner.invoke(app, [*args, "--scale", str(SCALE), "-o", str(gif)])
    assert result.exit_code == 0, result.output
    alone = {seed: runner.invoke(app, ["rollout", EVAL_LEVEL, "--policy", policy, "--seed", seed]) for seed in "01"}
    assert _outcomes(alone["0"].output) != _outcomes(alone["1"].output)
    assert _outcomes(result.output)[1] == _outcomes(alone["1"].output)[0]
    w, h = frame_size(SCALE)
    with Image.open(gif) as image:
        assert image.width == w + 2 * 6 and image.height > 2 * h + 3 * 6  # one column: two rows


def test_bad_input_is_one_line(capsys, tmp_path):
    line = kinetix(capsys, "rollout", PAD, "no/such/level.json", "--policy", "noop").error_line
    assert "no/such/level.json: no such file or folder" in line
    no_solution = tmp_path / "bare.json"
    no_solution.write_text(json.dumps({k: v for k, v in json.loads(Path(PAD).read_text()).items() if k != "solution"}))
    line = kinetix(capsys, "rollout", PAD, str(no_solution), "--policy", "solution").error_line
    assert "the level ships no solution" in line
    line = kinetix(capsys, "rollout", "validation", "--policy", "noop", "-o", tmp_path / "x.gif").error_line
    assert "one GIF shows at most 16" in line
    assert not (tmp_path / "x.gif").exists()
