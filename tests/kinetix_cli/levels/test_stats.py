"""Level-set statistics count what the levels hold."""

from __future__ import annotations

import jax

from engine import SIZES
from kinetix_cli.env.level import stack_levels
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.stats import level_statistics


def test_level_statistics_count_what_the_levels_hold():
    # rocket-car-jump: 1 polygon, 2 circles, 1 motor joint, 1 thruster; pad-to-pad: 1 polygon, 2 circles, 1 thruster
    files = ["levels/s/rocket-car-jump.json", "levels/s/pad-to-pad.json"]
    levels = jax.device_get(stack_levels([load_level(f).build(SIZES["s"]) for f in files]))
    stats = level_statistics("s", levels)
    per = stats["per level"]
    assert stats["levels"] == 2
    assert per["polygons"] == {"mean": 1.0, "min": 1, "max": 1} and per["circles"]["mean"] == 2.0
    assert per["motors"] == {"mean": 0.5, "min": 0, "max": 1} and per["thrusters"]["min"] == 1
    assert stats["levels with a motor"] == 1 and stats["levels with a thruster"] == 2
    assert stats["floor role"]["red"] == 1  # pad-to-pad's floor is red
