"""Domain randomisation, the baseline: every update trains on levels drawn uniformly from the level source (fresh
levels sampled for the update, or the pool): PPO's own update, `rl.ppo.ppo_update`."""

from __future__ import annotations

import dataclasses

from kinetix_cli.rl.curricula.base import Curriculum
from kinetix_cli.rl.ppo import ppo_update


@dataclasses.dataclass(frozen=True)
class DomainRandomisation(Curriculum):
    """No buffer, nothing before the update, nothing more to log."""

    def update(self, runner, env_params, pool):
        return ppo_update(
            runner, env_params, pool, env=self.env, network=self.network, settings=self.settings, fresh=self.fresh
        )
