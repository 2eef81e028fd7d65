"""ACCEL (Parker-Holder et al., 2022): robust PLR (`plr.py`) whose candidates are also mutations of buffer levels,
`curriculum.edits` random edits each (`generator.mutate`: add, move, rotate, resize shapes, swap roles, ...). Each
replay is followed by a mutation round: replay, mutation and new levels with probabilities p, p and 1 - p over
1 + p (p = `curriculum.replay_prob`)."""

from __future__ import annotations

import dataclasses

import jax

from kinetix_cli.config import CurriculumSettings
from kinetix_cli.env.environment import KinetixEnv
from kinetix_cli.env.level import Level
from kinetix_cli.generator.mutate import mutate_level
from kinetix_cli.rl.curricula.plr import PLR


def mutate_levels(key: jax.Array, levels: Level, env: KinetixEnv, curriculum: CurriculumSettings) -> Level:
    """Each of a batch of levels after `curriculum.edits` random edits, one key per level."""
    count = jax.tree.leaves(levels)[0].shape[0]
    edit = lambda k, level: mutate_level(env.static, k, level, edits=curriculum.edits)  # noqa: E731
    return jax.vmap(edit)(jax.random.split(key, count), levels)


@dataclasses.dataclass(frozen=True)
class ACCEL(PLR):
    """PLR with `mutate_levels` as its mutation."""

    mutation = staticmethod(mutate_levels)
