"""Contact sheets: many levels side by side in one picture, each under its caption.

Examples:
    Three shipped levels, two to a row, at 20 px/m; `render.save_png(sheet, "levels-s.png")` writes it:

    >>> from kinetix_cli.levels.files import load_level
    >>> from kinetix_cli.levels.suites import suite_folder
    >>> paths = sorted(suite_folder("s").glob("*.json"))[:3]
    >>> sheet = contact_sheet([(load_level(path).build(), path.stem) for path in paths], columns=2, scale=20)
    >>> frame_size(20), sheet.size  # two rows of two tiles (the last one empty), 8 px gaps
    ((104, 129), (232, 282))
"""

from __future__ import annotations

from PIL import Image

from kinetix_cli.env.level import Level
from kinetix_cli.viz.render import frame_size, render_level

GAP_COLOUR = (255, 255, 255)
"""Colour of the gaps between and around the tiles."""


def contact_sheet(levels: list[tuple[Level, str]], columns: int, scale: float = 40, *, gap: int = 8) -> Image.Image:
    """Render each level (`render_frame(..., title=caption)`) and tile the frames row by row in a grid.

    Args:
        levels: (level, caption) pairs: one scene each (numpy or jax leaves, no batch axis), any sizes.
        columns: tiles per row (>= 1); a sheet with fewer levels than `columns` is one row of them.
        scale: pixels per metre of each frame [px/m].
        gap: white space between the tiles and around the sheet [px].

    Returns:
        An RGB image of `cols * w + (cols + 1) * gap` by `rows * h + (rows + 1) * gap` pixels, where
        (w, h) = `render.frame_size(scale)`, cols = min(columns, len(levels)) and rows = ceil(len / cols).
    """
    if not levels:
        raise ValueError("contact_sheet: need at least one level")
    if columns < 1:
        raise ValueError(f"contact_sheet: columns must be >= 1, got {columns}")
    if gap < 0:
        raise ValueError(f"contact_sheet: gap must be >= 0 px, got {gap}")
    cols = min(columns, len(levels))
    rows = -(-len(levels) // cols)
    width, height = frame_size(scale)
    sheet = Image.new("RGB", (cols * width + (cols + 1) * gap, rows * height + (rows + 1) * gap), GAP_COLOUR)
    for k, (level, caption) in enumerate(levels):
        row, col = divmod(k, cols)
        frame = render_level(level, scale=scale, title=caption)
        sheet.paste(frame, (gap + col * (width + gap), gap + row * (height + gap)))
    return sheet
