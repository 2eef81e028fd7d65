"""The training levels of a run (`levels.source` in the experiment config): a pool on the device (level files, a
level set, or levels generated at the start of the run), or fresh levels sampled inside every training update."""

from __future__ import annotations

import jax
import numpy as np
from jax.sharding import Mesh

from engine import SIZES
from kinetix_cli.config import ExperimentConfig
from kinetix_cli.constants import VALIDATION_SEED
from kinetix_cli.env.level import Level, index_level, level_count, stack_levels, to_device
from kinetix_cli.errors import UserError
from kinetix_cli.generator.filters import chunk_source, make_config
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.levelset import load_levelset, solved_rows


def fresh_source(config: ExperimentConfig) -> FreshLevels | None:
    """The in-graph sampler of source 'fresh', else None."""
    if config.levels.source != "fresh":
        return None
    return FreshLevels.for_size(SIZES[config.env.size], config.env.size, like=config.levels.fresh_like)


def pool_seed(run_seed: int, round: int) -> int:
    """The generation seed of a generated pool's `round` (`levels.refresh_every`): the run's seed for round 0,
    then a seed of its own derived from (run seed, round), below the validation suite's (`VALIDATION_SEED`)."""
    if round == 0:
        return run_seed
    return int(np.random.SeedSequence([run_seed, round]).generate_state(1)[0] & 0x7FFFFFFF) % VALIDATION_SEED


def level_pool(config: ExperimentConfig, mesh: Mesh | None = None, round: int = 0) -> Level | None:
    """The training levels as one batch of device arrays: level files (each with its own engine constants), a
    level set, or `levels.pool_size` generated levels (filtered, seeded by `pool_seed(run.seed, round)`; generated
    on the `mesh`'s devices when given, one chunk per device: the same levels on any mesh); None for source 'fresh'.

    A multi-process run generates the pool in every process on its local devices (a local mesh): each process
    gets the whole pool with the program `kinetix generate` runs on one device, and no array of the run's global
    mesh is involved."""
    settings, size = config.levels, config.env.size
    if settings.source == "fresh":
        return None
    if settings.source == "files":
        return stack_levels([load_level(path).build(SIZES[size]) for path in settings.files])
    if settings.source == "levelset":
        levelset = load_levelset(settings.levelset)
        if levelset.manifest["size"] != size:
            raise UserError(f"{settings.levelset}: holds size-{levelset.manifest['size']} levels, env.size is {size}")
        if settings.solved_only:  # the levels its search solved
            return to_device(
                index_level(levelset.levels, solved_rows(levelset, settings.levelset, "levels.solved_only"))
            )
        return to_device(levelset.levels)
    chunk = chunk_source(make_config(size, settings.pool_chunk), pool_seed(config.run.seed, round), mesh)
    chunks, kept, index = [], 0, 0
    while kept < settings.pool_size:
        levels, _ = chunk(index)
        chunks.append(levels)
        kept += level_count(levels)
        index += 1
    return to_device(jax.tree.map(lambda *xs: np.concatenate(xs)[: settings.pool_size], *chunks))
