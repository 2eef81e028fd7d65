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

import functools

import flax.linen as nn
import jax
import jax.numpy as jnp

from kinetix_cli.config import CurriculumSettings, PPOSettings
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.level import Level, draw_levels
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.parallel import batch_sharded, replicated
from kinetix_cli.rl.buffer import LevelBuffer, draw_from_buffer, top_levels
from kinetix_cli.rl.ppo import Runner, first_reset, train_on, update_keys


def episode_counts(
    params,
    env_params: EnvParams,
    levels: Level,
    key: jax.Array,
    *,
    env: KinetixEnv,
    network: nn.Module,
    steps: int,
    attempts: int = 1,
) -> tuple[jax.Array, jax.Array]:
    """Solved and ended episodes, each (batch,) float32, of the sampling policy on each of a batch of levels:
    `attempts` copies of each level played side by side for `steps` environment steps, every ended episode
    restarted on the same level, all copies counted together."""
    count = jax.tree.leaves(levels)[0].shape[0]
    levels = jax.tree.map(lambda x: jnp.repeat(x, attempts, axis=0), levels)  # copies of a level are adjacent
    obs, state = jax.vmap(env.reset_to_level)(levels)
    step = jax.vmap(env.step, in_axes=(0, 0, None, 0))

    def play(carry, key):
        obs, state, ended, solved = carry
        action = network.apply(params, obs)[0].sample(key)
        obs, state, _, terminated, truncated, info = step(state, action, env_params, levels)
        return (obs, state, ended + (terminated | truncated), solved + info["solved"]), None

    zeros = jnp.zeros(count * attempts, jnp.float32)
    (_, _, ended, solved), _ = jax.lax.scan(play, (obs, state, zeros, zeros), jax.random.split(key, steps))
    return solved.reshape(count, attempts).sum(1), ended.reshape(count, attempts).sum(1)


@functools.partial(jax.jit, static_argnames=("env", "network", "fresh", "curriculum"))
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
    """Score `curriculum.score_levels` candidates (fresh levels, or draws from `pool`) in batches of
    `score_batch` and return the `buffer_size` most learnable as the new buffer (its scoring rounds counted on
    from the old `buffer`'s; `update` stamps the levels' `last_seen`)."""
    batch = curriculum.score_batch

    def score_batch(key):
        k_levels, k_play = jax.random.split(key)
        levels = fresh(k_levels, batch) if fresh is not None else draw_levels(pool, k_levels, batch)
        levels = batch_sharded(levels)  # under a mesh, each device scores its share of the batch
        solved, ended = episode_counts(
            params,
            env_params,
            levels,
            k_play,
            env=env,
            network=network,
            steps=curriculum.score_steps,
            attempts=curriculum.score_attempts,
        )
        return levels, solved / jnp.maximum(ended, 1.0)  # p, 0 when no episode ended

    keys = jax.random.split(key, curriculum.score_levels // batch)
    levels, rates = jax.lax.map(score_batch, keys)
    levels, rates = jax.tree.map(lambda x: x.reshape((-1, *x.shape[2:])), (levels, rates))
    seen = jnp.full(rates.shape, update, jnp.int32)
    rounds = buffer.rounds + 1
    scores, best = rates * (1.0 - rates), jnp.zeros_like(rates)
    buffer = top_levels(levels, scores, rates, curriculum.buffer_size, seen, best, rounds)
    return replicated(buffer)  # one global buffer, a copy on every device


@functools.partial(jax.jit, static_argnames=("env", "network", "settings", "fresh", "curriculum"))
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
