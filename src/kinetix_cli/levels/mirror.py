"""Mirror images of level files and level sets (`kinetix levels mirror`), through `env.mirror.mirror_level`.

A mirrored level file is written by `export_level` (bodies named polygon-0, ..., circle-0, ... as in every
exported level), named "<name> (mirrored)", with the level's solution mirrored too (motor entries 1 <-> 2), so
`kinetix validate` replays it on the mirror image. A mirrored level set is a level set whose level i is the mirror
of the source's level i, written by the level-set driver (resumable, byte-reproducible); its manifest's
`settings` names the source: its size, count, seed, settings and shard digests.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import jax
import numpy as np

from kinetix_cli.env.level import Level, to_host
from kinetix_cli.env.mirror import mirror_action, mirror_level
from kinetix_cli.levels.export import export_level
from kinetix_cli.levels.levelset import generate_levelset, load_levelset
from kinetix_cli.levels.parse import LevelSpec
from kinetix_cli.levels.solution import SOLUTION_SETTINGS, decode_solution, encode_solution

CHUNK = 1024
"""Levels of a set mirrored per call."""
_mirror_batch = jax.jit(jax.vmap(mirror_level))


def mirrored_level_data(spec: LevelSpec) -> dict:
    """The `kinetix-level/1` data of the mirror image of a level, its solution (if any) mirrored."""
    static = spec.default_static()
    data = export_level(
        to_host(mirror_level(spec.build(static))),
        static,
        name=f"{spec.name} (mirrored)",
        description=f"Mirror image (x -> 5 - x) of {spec.source}"
        + (f": {spec.description}" if spec.description else ""),
    )
    if spec.solution is not None:
        actions = decode_solution(spec.solution, spec.source, SOLUTION_SETTINGS.max_steps)
        data["solution"] = encode_solution(np.asarray(mirror_action("multi-discrete", actions)), len(actions))
    return data


def mirror_levelset(source: Path, out: Path, progress: Callable[[int, dict], None] | None = None) -> dict:
    """Write the mirror image of the level set in `source` into `out`; returns the new set's manifest."""
    levelset = load_levelset(source)
    manifest = levelset.manifest
    count = manifest["count"]

    def chunk(i: int) -> tuple[Level, dict]:
        rows = jax.tree.map(lambda x: x[i * CHUNK : (i + 1) * CHUNK], levelset.levels)
        return to_host(_mirror_batch(rows)), {"mirrored": len(rows.bindings.motor)}

    source_identity = {key: manifest[key] for key in ("size", "count", "seed", "settings")}
    settings = {"mirror_of": source_identity | {"shards": [shard["sha256"] for shard in manifest["shards"]]}}
    return generate_levelset(
        out,
        size=manifest["size"],
        count=count,
        seed=manifest["seed"],
        settings=settings,
        chunk_fn=chunk,
        shard_size=manifest["shard_size"],
        progress=progress,
    )
