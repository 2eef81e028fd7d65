"""A small level set written without compiling anything: shipped s levels stored through the level-set writer."""

from __future__ import annotations

from pathlib import Path

import jax

from engine import SIZES
from helpers.paths import LEVELS
from kinetix_cli.env.level import stack_levels
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.levelset import generate_levelset

FILES = sorted((LEVELS / "s").glob("*.json"))[:6]


def small_levelset(out: Path, shard_size: int = 4) -> dict:
    """Write a 6-level size-s set (shards of `shard_size`) into `out`; returns its manifest."""
    levels = jax.device_get(stack_levels([load_level(f).build(SIZES["s"]) for f in FILES]))
    return generate_levelset(
        out,
        size="s",
        count=len(FILES),
        seed=0,
        settings={"source": "shipped s levels"},
        chunk_fn=lambda i: (levels, {"sampled": len(FILES)}),
        shard_size=shard_size,
    )
