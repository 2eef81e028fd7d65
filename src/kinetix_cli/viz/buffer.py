"""A run's curriculum buffer as levels to draw (`kinetix levels show RUN --buffer`, `kinetix report`): the levels
of its latest checkpoint's buffer, highest score first (SFL: learnability), each captioned with its solve rate and
score when it was last played."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from engine import SIZES
from kinetix_cli.config import CONFIG_FILENAME, load_config
from kinetix_cli.env.level import Level, index_level
from kinetix_cli.errors import UserError
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.rl.checkpoints import load_buffer


def buffer_levels(run: Path, first: int, count: int) -> list[tuple[Level, str]]:
    """(level, caption) of buffer levels first .. first + count - 1 (best first) of a run's latest checkpoint;
    none when the buffer is still empty."""
    config_file = run / CONFIG_FILENAME
    if not config_file.is_file():
        raise UserError(f"{run}: not a run directory (no {CONFIG_FILENAME}); --buffer draws a training run's buffer")
    size = load_config(config_file).env.size
    buffer, update = load_buffer(run, FreshLevels.for_size(SIZES[size], size).placeholder())
    filled = int(buffer.size)
    if filled == 0:
        return []
    if not 0 <= first < filled:
        raise UserError(f"--index: {first} is out of range; the buffer holds levels 0..{filled - 1}")
    order = np.argsort(-np.asarray(buffer.score[:filled]), kind="stable")  # best first (PLR rescores in place)
    captions = [
        f"#{i} p={buffer.solve_rate[j]:.2f} score={buffer.score[j]:.3f} (update {update})" for i, j in enumerate(order)
    ]
    return [(index_level(buffer.levels, order[i]), captions[i]) for i in range(first, min(first + count, filled))]
