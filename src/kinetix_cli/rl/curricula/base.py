"""The one interface every curriculum implements: which levels an update trains on, what runs before it, what the
run logs of it, and what it keeps in the checkpoint.

`rl.train` drives a `Curriculum` without knowing which one it is:

    runner = init_runner(..., buffer_size=curriculum.buffer_size)   # what it checkpoints: a LevelBuffer or none
    for u in updates:
        runner = curriculum.before_update(runner, env_params, pool, key, u)   # SFL scores its buffer here
        runner, metrics = curriculum.update(runner, env_params, pool)         # the levels, then PPO on them
        record = curriculum.logged(metrics) | curriculum.metrics(runner, steps)
"""

from __future__ import annotations

import dataclasses

import flax.linen as nn
import jax

from kinetix_cli.config import CurriculumSettings, PPOSettings
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.level import Level
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.rl.buffer import buffer_metrics
from kinetix_cli.rl.ppo import Runner


@dataclasses.dataclass(frozen=True)
class Curriculum:
    """A curriculum for one run: its environment, network, PPO settings, level source and settings.

    Attributes:
        env: the training environment.
        network: the actor-critic.
        settings: the run's `ppo` section.
        fresh: the in-graph sampler of source 'fresh', else None (levels come from the pool).
        curriculum: the run's `curriculum` section.
    """

    env: KinetixEnv
    network: nn.Module
    settings: PPOSettings
    fresh: FreshLevels | None
    curriculum: CurriculumSettings

    @property
    def buffer_size(self) -> int:
        """Slots of the `LevelBuffer` the curriculum carries in the runner, and so in every checkpoint (0: none)."""
        return 0

    @classmethod
    def split_sizes(cls, curriculum: CurriculumSettings) -> dict[str, int]:
        """The global size of every batch the curriculum splits across devices, by the setting that sets it."""
        return {}

    def before_update(self, runner: Runner, env_params: EnvParams, pool: Level | None, key: jax.Array, update: int):
        """The runner before update `update` (0-based); `key` is the update's own stream, a function of the update
        alone, so a resumed run does exactly what an uninterrupted one does."""
        return runner

    def update(self, runner: Runner, env_params: EnvParams, pool: Level | None) -> tuple[Runner, dict]:
        """One training update on the levels the curriculum chooses from the pool (or fresh levels): the new
        runner and the update's metrics (device scalars)."""
        raise NotImplementedError

    def logged(self, metrics: dict) -> dict:
        """An update's metrics (host floats) as the run logs them."""
        return metrics

    def scoring_steps(self, runner: Runner) -> tuple[int, bool]:
        """Environment steps spent scoring levels so far, and whether they come on top of the updates' steps."""
        return 0, False

    def metrics(self, runner: Runner, steps: int) -> dict:
        """What the run logs of the curriculum after an update, `steps` being the updates' environment steps so
        far: `total_steps` (every environment step, scoring included) and, with a buffer, its size, mean score and
        solve-rate distribution (`rl.buffer.buffer_metrics`), the steps spent scoring levels rather than training
        on them (`scoring_steps`) and their share of `total_steps` (`scoring_share`)."""
        if runner.buffer is None:
            return {"total_steps": steps}
        scoring, extra = self.scoring_steps(runner)
        total = steps + scoring if extra else steps
        buffer = {k: float(v) for k, v in jax.device_get(buffer_metrics(runner.buffer)).items()}
        return buffer | {"total_steps": total, "scoring_steps": scoring, "scoring_share": scoring / total}
