"""SFL, sampling for learnability (Rutherford et al., 2024; the Kinetix paper's best general agents).

Every `curriculum.refresh_every` updates, `score_levels` candidate levels are drawn from the level source (fresh
random levels, or the pool) and the current policy plays `score_attempts` copies of each for `score_steps`
environment steps, restarting the same level whenever an episode ends. A level's solve rate p is its solved
episodes over its ended episodes, all copies together (0 when none ended); its learnability is p (1 - p):
highest for levels solved half of the time, zero for levels always or never solved. The `buffer_size` most
learnable levels replace the buffer. `sfl_update` is PPO's update with `buffer_share` of each update's pool drawn
from the buffer and the rest from the source.
"""

from __future__ import annotations

import dataclasses
import functools

import flax.linen as nn
import jax
import jax.numpy as jnp

from kinetix_cli.config import CurriculumSettings, PPOSettings
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.episode import run_episode
from kinetix_cli.env.level import Level, draw_levels
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.parallel import batch_sharded, replicated
from kinetix_cli.rl.buffer import LevelBuffer, draw_from_buffer, top_levels
from kinetix_cli.rl.curricula.base import Curriculum
from kinetix_cli.rl.networks import sampling_policy
from kinetix_cli.rl.ppo import Runner, first_reset, train_on, update_keys
from kinetix_cli.trace_cache import cached_jit, compiling


def episode_counts(
    params,
    env_params: EnvParams,
    levels: Level,
    keys: jax.Array,
    *,
    env: KinetixEnv,
    network: nn.Module,
    steps: int,
    attempts: int = 1,
) -> tuple[jax.Array, jax.Array]:
    """Solved and ended episodes, each (batch,) float32, of the sampling policy on each of a batch of levels:
    `attempts` copies of each level played side by side for `steps` environment steps by the episode runner
    (`env.episode.run_episode` with `restart`: every ended episode restarts on the same level), all copies counted
    together. `keys` holds one key per copy, (batch x attempts,), a level's copies adjacent."""
    count = jax.tree.leaves(levels)[0].shape[0]
    levels = jax.tree.map(lambda x: jnp.repeat(x, attempts, axis=0), levels)  # copies of a level are adjacent
    play = functools.partial(
        run_episode, env, env_params, policy=sampling_policy(network, params), horizon=steps, restart=True
    )
    outcome = jax.vmap(lambda level, k: play(level, key=k))(levels, keys)
    counted = lambda x: x.astype(jnp.float32).reshape(count, attempts).sum(1)  # noqa: E731
    return counted(outcome.solves), counted(outcome.episodes)


@cached_jit(static_argnames=("env", "network", "fresh", "curriculum"))
def refresh_buffer(
    params,
    env_params: EnvParams,
    pool: Level | None,
    key: jax.Array,
    *,
    env: KinetixEnv,
    network: nn.Module,
    fresh: FreshLevels | None,
    curriculum: CurriculumSettings,
    buffer: LevelBuffer,
    update: jax.Array,
) -> LevelBuffer:
    """Score `curriculum.score_levels` candidates (fresh levels, or draws from `pool`) and return the
    `buffer_size` most learnable as the new buffer (its scoring rounds counted on from the old `buffer`'s;
    `update` stamps the levels' `last_seen`).

    The candidates are drawn `score_batch` to a key, one key after another (which bounds the generator's memory),
    and then played all at once, every copy of every candidate in one batched episode run: `score_steps` steps in
    sequence per refresh, not per batch, which a device wide enough to hold them all (a GPU) needs. The levels and
    keys are those that scoring each batch on its own drew."""
    batch, attempts = curriculum.score_batch, curriculum.score_attempts

    def draw(key):  # one key's candidates and the keys of their copies' episodes
        k_levels, k_play = jax.random.split(key)
        levels = fresh(k_levels, batch) if fresh is not None else draw_levels(pool, k_levels, batch)
        return levels, jax.random.split(k_play, batch * attempts)

    levels, keys = jax.lax.map(draw, jax.random.split(key, curriculum.score_levels // batch))
    levels, keys = jax.tree.map(lambda x: x.reshape((-1, *x.shape[2:])), (levels, keys))
    levels = batch_sharded(levels)  # under a mesh, each device scores its share of the candidates
    solved, ended = episode_counts(
        params,
        env_params,
        levels,
        batch_sharded(keys),
        env=env,
        network=network,
        steps=curriculum.score_steps,
        attempts=attempts,
    )
    rates = solved / jnp.maximum(ended, 1.0)  # p, 0 when no episode ended
    seen = jnp.full(rates.shape, update, jnp.int32)
    rounds = buffer.rounds + 1
    scores, best = rates * (1.0 - rates), jnp.zeros_like(rates)
    buffer = top_levels(levels, scores, rates, curriculum.buffer_size, seen, best, rounds)
    return replicated(buffer)  # one global buffer, a copy on every device


@cached_jit(static_argnames=("env", "network", "settings", "fresh", "curriculum"))
def sfl_update(
    runner: Runner,
    env_params: EnvParams,
    levels: Level | None,
    *,
    env: KinetixEnv,
    network: nn.Module,
    settings: PPOSettings,
    fresh: FreshLevels | None,
    curriculum: CurriculumSettings,
) -> tuple[Runner, dict]:
    """One PPO update (`rl.ppo.train_on`) whose pool is round(buffer_share x num_envs) levels drawn from the
    runner's buffer and the rest from the source: fresh levels (`fresh`) or draws from the pool `levels`."""
    n = settings.num_envs
    from_buffer = round(curriculum.buffer_share * n)
    runner, k_source, k_buffer, k_first = update_keys(runner)
    source = fresh(k_source, n - from_buffer) if fresh is not None else draw_levels(levels, k_source, n - from_buffer)
    buffered = draw_from_buffer(runner.buffer, k_buffer, from_buffer)
    pool = batch_sharded(jax.tree.map(lambda a, b: jnp.concatenate([a, b]), buffered, source))
    if fresh is not None:
        runner = first_reset(runner, env, pool, k_first)
    return train_on(runner, env_params, pool, env=env, network=network, settings=settings)


@dataclasses.dataclass(frozen=True)
class SFL(Curriculum):
    """Sampling for learnability: a buffer of `curriculum.buffer_size` levels, scored again before every
    `curriculum.refresh_every`-th update (its rollouts come on top of the updates' steps)."""

    @property
    def buffer_size(self) -> int:
        return self.curriculum.buffer_size

    @classmethod
    def split_sizes(cls, curriculum) -> dict[str, int]:
        return {"curriculum.score_levels": curriculum.score_levels}

    def before_update(self, runner, env_params, pool, key, update):
        if update % self.curriculum.refresh_every:
            return runner
        refresh = self._refresh(runner, env_params, pool, key, update)
        with compiling(self._update(runner, env_params, pool)):  # loads while the refresh loads and scores
            return runner.replace(buffer=refresh())

    def update(self, runner, env_params, pool):
        return self._update(runner, env_params, pool)()

    def _refresh(self, runner, env_params, pool, key, update) -> functools.partial:
        """The buffer's refresh, as a call with its arguments."""
        parts = {"env": self.env, "network": self.network, "fresh": self.fresh, "curriculum": self.curriculum}
        return functools.partial(
            refresh_buffer, runner.params, env_params, pool, key, **parts, buffer=runner.buffer, update=update
        )

    def _update(self, runner, env_params, pool) -> functools.partial:
        """The update, as a call with its arguments (a refreshed buffer has the types of the one it replaces: the
        same program)."""
        parts = {"env": self.env, "network": self.network, "settings": self.settings, "fresh": self.fresh}
        return functools.partial(sfl_update, runner, env_params, pool, **parts, curriculum=self.curriculum)

    def scoring_steps(self, runner):
        return int(runner.buffer.rounds) * self.curriculum.scoring_steps, True
