"""Curricula: which levels training episodes start from (`curriculum.name` in the experiment config).

Each is one module implementing the one interface, `base.Curriculum` (the levels of an update, what runs before
it, what is logged, what is checkpointed):

- `dr` (`dr.py`, domain randomisation, the baseline): uniformly from the level source (`levels.source`: fresh
  levels sampled every update, or a fixed pool): `rl.ppo.ppo_update` itself.
- `sfl` (`sfl.py`, sampling for learnability): a buffer of the levels the current policy solves about half of
  the time, refreshed every `curriculum.refresh_every` updates; a share of the episodes start from it.
- `plr` (`plr.py`, robust prioritised level replay): every update either replays buffer levels and trains on them,
  or scores new levels without training.
- `accel` (`accel.py`): PLR whose candidates are also mutations of buffer levels.

Curricula keep their levels in a `rl.buffer.LevelBuffer` (levels, scores, solve rates), carried in the PPO `Runner`
and so saved in every checkpoint: a resumed run ends bit-identical to an uninterrupted one.
"""

from __future__ import annotations

import flax.linen as nn

from kinetix_cli.config import CurriculumSettings, PPOSettings
from kinetix_cli.env.environment import KinetixEnv
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.rl.curricula.accel import ACCEL
from kinetix_cli.rl.curricula.base import Curriculum
from kinetix_cli.rl.curricula.dr import DomainRandomisation
from kinetix_cli.rl.curricula.plr import PLR
from kinetix_cli.rl.curricula.sfl import SFL

CURRICULA: dict[str, type[Curriculum]] = {"dr": DomainRandomisation, "sfl": SFL, "plr": PLR, "accel": ACCEL}
"""Every curriculum by its `curriculum.name`."""


def curriculum_class(settings: CurriculumSettings) -> type[Curriculum]:
    """The class of the configured curriculum."""
    return CURRICULA[settings.name]


def make_curriculum(
    settings: CurriculumSettings,
    *,
    env: KinetixEnv,
    network: nn.Module,
    ppo: PPOSettings,
    fresh: FreshLevels | None,
) -> Curriculum:
    """The configured curriculum for a run of this environment, network, PPO settings and level source."""
    return curriculum_class(settings)(env, network, ppo, fresh, settings)
