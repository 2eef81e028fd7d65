"""Small level sets: shipped s levels stored through the level-set writer (without compiling anything), and
solved sets of them with their shipped solutions; the generated chunk the generator's tests share."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import jax
import numpy as np
import pytest

from engine import SIZES
from helpers.paths import LEVELS
from kinetix_cli.env.episode import replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import stack_levels
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.levelset import SOLUTION_STEPS, Solutions, generate_levelset
from kinetix_cli.levels.solution import SOLUTION_SETTINGS, decode_solution

FILES = sorted((LEVELS / "s").glob("*.json"))[:6]

CHUNK = 32
"""Levels sampled per chunk by the generator's tests: `kinetix generate --chunk 32` and the `first_chunk` fixture."""
GENERATE_GROUP = pytest.mark.xdist_group("generate-s-32")
"""`pytestmark` of the modules that generate chunks of `CHUNK` size-s levels: one worker compiles the program."""


def small_levelset(
    out: Path,
    shard_size: int = 4,
    files: list[Path] = FILES,
    per_chunk: int | None = None,
    before_chunk: Callable[[int], None] | None = None,
    solutions: Solutions | None = None,
) -> dict:
    """Write a set of the size-s level `files` (default: 6 shipped levels; shards of `shard_size`) into `out`;
    returns its manifest. The levels come in one chunk, or `per_chunk` at a time; `before_chunk(i)` runs before
    chunk i is handed over (to fail the writes from there on). With `solutions` (one row per file) a solved set."""
    levels = jax.device_get(stack_levels([load_level(f).build(SIZES["s"]) for f in files]))
    step = per_chunk or len(files)

    def chunk(i: int):
        if before_chunk is not None:
            before_chunk(i)
        rows = slice(i * step, (i + 1) * step)
        if solutions is None:
            return jax.tree.map(lambda x: x[rows], levels), {"sampled": step}
        found = Solutions(*(x[rows] for x in (solutions.actions, solutions.solved, solutions.length)))
        stats = {"solved": int(found.solved.sum()), "unsolved": int((~found.solved).sum())}
        return jax.tree.map(lambda x: x[rows], levels), stats, found

    return generate_levelset(
        out,
        size="s",
        count=len(files),
        seed=0,
        settings={"source": "shipped s levels"},
        chunk_fn=chunk,
        shard_size=shard_size,
        solutions=solutions is not None,
    )


def solved_levelset(out: Path, files: list[Path], unsolved: int = 0) -> dict:
    """Write a solved set of the size-s level `files` with their shipped solutions (the last `unsolved` marked
    unsolved, no-op actions) into `out`; returns its manifest. Lengths come from replaying the solutions."""
    levels = jax.device_get(stack_levels([load_level(f).build(SIZES["s"]) for f in files]))
    actions = np.stack([decode_solution(load_level(f).solution, str(f), SOLUTION_STEPS) for f in files])
    env, params = make_env(SOLUTION_SETTINGS, SIZES["s"])
    outcome = replay(env, params, levels, actions)
    solved = np.asarray(outcome.solved) & (np.arange(len(files)) < len(files) - unsolved)
    length = np.where(solved, np.asarray(outcome.length), 0).astype(np.int32)
    actions = np.where(solved[:, None, None], actions, 0).astype(np.int8)
    actions[np.arange(SOLUTION_STEPS)[None, :] >= length[:, None]] = 0
    return small_levelset(out, files=files, solutions=Solutions(actions, solved, length))
