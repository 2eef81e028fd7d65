"""Contact sheets: grid size, white gaps, one rendered frame per tile."""

from __future__ import annotations

import numpy as np
import pytest

from helpers.paths import LEVELS
from kinetix_cli.levels.files import load_level
from kinetix_cli.viz.contact_sheet import contact_sheet
from kinetix_cli.viz.render import frame_size, render_level

S_LEVELS = sorted((LEVELS / "s").glob("*.json"))[:5]
SCALE, GAP = 20, 6


def test_five_levels_in_three_columns():
    levels = [(load_level(path).build(), path.stem) for path in S_LEVELS]
    sheet = contact_sheet(levels, columns=3, scale=SCALE, gap=GAP)
    w, h = frame_size(SCALE)
    assert sheet.mode == "RGB"
    assert sheet.size == (3 * w + 4 * GAP, 2 * h + 3 * GAP)
    pixels = np.asarray(sheet)
    assert np.all(pixels[:GAP] == 255) and np.all(pixels[:, w + GAP : w + 2 * GAP] == 255)
    assert np.all(pixels[h + 2 * GAP :, 2 * w + 3 * GAP :] == 255)  # the sixth tile is empty
    fifth = render_level(levels[4][0], scale=SCALE, title=levels[4][1])
    top, left = h + 2 * GAP, w + 2 * GAP
    np.testing.assert_array_equal(pixels[top : top + h, left : left + w], np.asarray(fifth))


def test_fewer_levels_than_columns_make_one_row():
    level = load_level(S_LEVELS[0]).build()
    sheet = contact_sheet([(level, "a"), (level, "b")], columns=4, scale=SCALE, gap=0)
    w, h = frame_size(SCALE)
    assert sheet.size == (2 * w, h)


def test_rejects_empty_and_zero_columns():
    with pytest.raises(ValueError, match="at least one"):
        contact_sheet([], columns=3)
    with pytest.raises(ValueError, match="columns"):
        contact_sheet([(load_level(S_LEVELS[0]).build(), "a")], columns=0)
