"""A small level set written without compiling anything: shipped s levels stored through the level-set writer."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import jax

from engine import SIZES
from helpers.paths import LEVELS
from kinetix_cli.env.level import stack_levels
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.levelset import generate_levelset

FILES = sorted((LEVELS / "s").glob("*.json"))[:6]


def small_levelset(
    out: Path,
    shard_size: int = 4,
    files: list[Path] = FILES,
    per_chunk: int | None = None,
    before_chunk: Callable[[int], None] | None = None,
) -> dict:
    """Write a set of the size-s level `files` (default: 6 shipped levels; shards of `shard_size`) into `out`;
    returns its manifest. The levels come in one chunk, or `per_chunk` at a time; `before_chunk(i)` runs before
    chunk i is handed over (to fail the writes from there on)."""
    levels = jax.device_get(stack_levels([load_level(f).build(SIZES["s"]) for f in files]))
    step = per_chunk or len(files)

    def chunk(i: int):
        if before_chunk is not None:
            before_chunk(i)
        rows = slice(i * step, (i + 1) * step)
        return jax.tree.map(lambda x: x[rows], levels), {"sampled": step}

    return generate_levelset(
        out,
        size="s",
        count=len(files),
        seed=0,
        settings={"source": "shipped s levels"},
        chunk_fn=chunk,
        shard_size=shard_size,
    )
