"""PPO, the PureJaxRL way: rollout, GAE and the update epochs in one jitted function over vmapped environments.

`ppo_update(runner, env_params, levels, env=..., network=..., settings=...)` is one PPO update of
`num_envs x num_steps` environment steps; the caller loops over updates (checkpoints, logging and resume live
outside the jit). The environment, the network and the `PPOSettings` section are static arguments (all three are
hashable by value), so every call with equal settings shares one compile; the level pool is an argument, so a new
pool of the same shape does not recompile either.

Episodes that end restart from a level drawn uniformly from the update's pool by the environment's own auto-reset
(`KinetixEnv.step`). The pool is `levels` (a fixed pool on the device: generated at the start, a level set, level
files) or, with the static `fresh` source (and `levels` None), a batch of `num_envs` new levels sampled at the
start of every update inside the jit (`kinetix_cli.generator.fresh`). A curriculum (`rl.curricula`) puts a share
of its buffer's levels into every update's pool.

Timeouts: an episode that hits the step cap is *truncated*, not terminated. Its last
transition bootstraps from the value of the final observation (`info["final_observation"]`, before the reset),
so the cap does not look like a failure to the critic. Every transition stores `next_value` = V(observation after
the step, before any reset); the GAE recursion stops at every episode boundary, and only true terminations (green
touched blue or red, NaN) zero the bootstrap.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import flax.linen as nn
import jax
import jax.numpy as jnp
import optax
from flax import struct

from kinetix_cli.config import CurriculumSettings, PPOSettings
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.level import Level, draw_levels, index_level
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.generator.mutate import mutate_level
from kinetix_cli.parallel import batch_sharded, replicated
from kinetix_cli.rl.curricula import plr
from kinetix_cli.rl.curricula.buffer import LevelBuffer, draw_from_buffer, empty_buffer


@struct.dataclass
class Transition:
    """One environment step of every env; a rollout stacks them to (num_steps, num_envs, ...)."""

    obs: Any
    action: jax.Array
    log_prob: jax.Array
    value: jax.Array  # V(obs)
    next_value: jax.Array  # V(observation after the step, before the auto-reset)
    reward: jax.Array
    terminated: jax.Array  # the episode ended by the task (or NaN): no bootstrap
    done: jax.Array  # terminated or truncated: the trace stops here
    solved: jax.Array


@struct.dataclass
class Runner:
    """The carry between updates: everything needed to continue training bit for bit.

    Attributes:
        params: network parameters.
        opt_state: optimiser state.
        env_state: batched environment state (num_envs, ...).
        obs: the current batched observation.
        episode_return: (num_envs,) return of the running episodes.
        key: PRNG key.
        update: () int32 updates done.
        buffer: the curriculum's level buffer (`rl.curricula.buffer.LevelBuffer`), or None (DR).
    """

    params: Any
    opt_state: Any
    env_state: Any
    obs: Any
    episode_return: jax.Array
    key: jax.Array
    update: jax.Array
    buffer: LevelBuffer | None = None

    def placed(self) -> Runner:
        """Under a device mesh: the environments split across the devices, everything else (parameters,
        optimiser state, key, the curriculum's buffer) replicated. Every jitted function that returns a runner
        places it so, so its next call sees the same shardings (and is not compiled again)."""
        batched = batch_sharded((self.env_state, self.obs, self.episode_return))
        shared = replicated((self.params, self.opt_state, self.key, self.update, self.buffer))
        return Runner(*shared[:2], *batched, *shared[2:])


def make_optimizer(settings: PPOSettings) -> optax.GradientTransformation:
    """Adam with global-norm gradient clipping; the learning rate decays linearly to 0 over the run when
    `anneal_lr`, else stays constant."""
    lr = settings.lr
    if settings.anneal_lr:
        total = settings.num_updates * settings.update_epochs * settings.num_minibatches
        lr = lambda count: settings.lr * (1.0 - jnp.minimum(count, total) / total)  # noqa: E731
    return optax.chain(optax.clip_by_global_norm(settings.max_grad_norm), optax.adam(lr, eps=settings.adam_eps))


def gae(transitions: Transition, gamma: float, gae_lambda: float) -> tuple[jax.Array, jax.Array]:
    """Generalised advantage estimates and value targets, both (num_steps, num_envs).

    delta_t = r_t + gamma * next_value_t * (1 - terminated_t) - value_t;
    A_t = delta_t + gamma * lambda * (1 - done_t) * A_{t+1}.
    """

    def backward(advantage, t: Transition):
        delta = t.reward + gamma * t.next_value * (1.0 - t.terminated) - t.value
        advantage = delta + gamma * gae_lambda * (1.0 - t.done) * advantage
        return advantage, advantage

    _, advantages = jax.lax.scan(backward, jnp.zeros_like(transitions.value[0]), transitions, reverse=True)
    return advantages, advantages + transitions.value


def entropy_weight(settings: PPOSettings, update: jax.Array) -> jax.Array | float:
    """The entropy bonus's weight at `update`: `ent_coef`, or with `ent_coef_end` the linear way between them
    over the run's updates."""
    if settings.ent_coef_end is None:
        return settings.ent_coef
    done = jnp.minimum(update, settings.num_updates - 1) / max(settings.num_updates - 1, 1)
    return settings.ent_coef + (settings.ent_coef_end - settings.ent_coef) * done


def ppo_loss(apply_fn, params, batch: Transition, advantages, targets, settings: PPOSettings, ent_coef):
    """Clipped policy loss + vf_coef * clipped value loss - ent_coef * entropy, and its parts."""
    dist, value = apply_fn(params, batch.obs)
    log_prob = dist.log_prob(batch.action)
    if settings.normalise_advantages:
        advantages = (advantages - advantages.mean()) / (advantages.std() + 1e-8)
    ratio = jnp.exp(log_prob - batch.log_prob)
    clipped_ratio = jnp.clip(ratio, 1.0 - settings.clip_eps, 1.0 + settings.clip_eps)
    policy_loss = -jnp.minimum(ratio * advantages, clipped_ratio * advantages).mean()
    value_clipped = batch.value + jnp.clip(value - batch.value, -settings.clip_eps, settings.clip_eps)
    value_loss = 0.5 * jnp.maximum((value - targets) ** 2, (value_clipped - targets) ** 2).mean()
    entropy = dist.entropy().mean()
    total = policy_loss + settings.vf_coef * value_loss - ent_coef * entropy
    approx_kl = ((ratio - 1.0) - jnp.log(ratio)).mean()
    return total, {"policy_loss": policy_loss, "value_loss": value_loss, "entropy": entropy, "approx_kl": approx_kl}


def update_levels(
    runner: Runner, env: KinetixEnv, levels: Level | None, fresh: FreshLevels | None, buffer_share: float, count: int
) -> tuple[Runner, Level]:
    """The levels this update's episodes restart from, and the runner with its key advanced.

    From the source: the pool `levels` as it is, or `count` fresh levels from `fresh`. With `buffer_share` > 0 (a
    curriculum), round(buffer_share * count) levels drawn from the runner's buffer and the rest from the source,
    `count` in all. Before the first update with a fresh source, every environment is also reset to one of them
    (`init_runner` started them on an empty arena)."""
    from_buffer = round(buffer_share * count)
    if fresh is None and not from_buffer:
        return runner, levels  # a fixed pool, uniformly: the key stream of runs before curricula, unchanged
    key, k_source, k_buffer, k_first = jax.random.split(runner.key, 4)
    if fresh is not None:
        pool = fresh(k_source, count - from_buffer)
    else:
        pool = draw_levels(levels, k_source, count - from_buffer)
    if from_buffer:
        buffered = draw_from_buffer(runner.buffer, k_buffer, from_buffer)
        pool = jax.tree.map(lambda a, b: jnp.concatenate([a, b]), buffered, pool)
    pool = batch_sharded(pool)
    runner = runner.replace(key=key)
    if fresh is not None:
        obs, env_state = jax.vmap(env.reset_to_level)(batch_sharded(draw_levels(pool, k_first, count)))
        first = runner.update == 0
        runner = runner.replace(
            obs=jax.tree.map(lambda a, b: jnp.where(first, a, b), obs, runner.obs),
            env_state=jax.tree.map(lambda a, b: jnp.where(first, a, b), env_state, runner.env_state),
        )
    return runner, pool


@functools.partial(jax.jit, static_argnums=(0, 1, 2), static_argnames=("fresh", "buffer_size"))
def init_runner(
    env: KinetixEnv,
    network: nn.Module,
    settings: PPOSettings,
    levels: Level | None,
    key: jax.Array,
    fresh: FreshLevels | None = None,
    buffer_size: int = 0,
) -> Runner:
    """Fresh parameters, optimiser state and `settings.num_envs` environments reset to pool levels, and an empty
    level buffer of `buffer_size` slots (0: none). With a `fresh` source (and no pool) the environments start on
    an empty arena and the first update resets them to its own fresh levels, so the sampler is compiled once, in
    `ppo_update`. Jitted (one compile per settings): run op by op, the reset and the network init cost hundreds
    of small compiles."""
    if fresh is not None:
        levels = fresh.placeholder()
    k_params, k_reset, key = jax.random.split(key, 3)
    obs, env_state = jax.vmap(env.reset_to_level)(batch_sharded(draw_levels(levels, k_reset, settings.num_envs)))
    params = network.init(k_params, obs)
    return Runner(
        params=params,
        opt_state=make_optimizer(settings).init(params),
        env_state=env_state,
        obs=obs,
        episode_return=jnp.zeros(settings.num_envs, jnp.float32),
        key=key,
        update=jnp.zeros((), jnp.int32),
        buffer=empty_buffer(levels, buffer_size) if buffer_size else None,
    ).placed()


def collect(
    runner: Runner,
    env_params: EnvParams,
    restart: Callable[[jax.Array], Level],
    *,
    env: KinetixEnv,
    network: nn.Module,
    num_steps: int,
) -> tuple[Runner, Transition, jax.Array]:
    """Play `num_steps` steps in every environment with the sampling policy. Episodes that end restart from
    `restart(key)`, a batch of one level per environment drawn at each step. Returns the runner (environments,
    observations, key and running returns advanced), the (num_steps, num_envs) transitions and the returns of the
    episodes that ended at each step (0 elsewhere)."""

    def env_step(runner: Runner, _):
        # --- act
        key, k_act, k_reset = jax.random.split(runner.key, 3)
        dist, value = network.apply(runner.params, runner.obs)
        action = dist.sample(k_act)
        log_prob = dist.log_prob(action)
        # --- step; ended episodes restart
        step = jax.vmap(env.step, in_axes=(0, 0, None, 0))
        obs, env_state, reward, terminated, truncated, info = step(
            runner.env_state, action, env_params, batch_sharded(restart(k_reset))
        )
        _, next_value = network.apply(runner.params, info["final_observation"])
        done = terminated | truncated
        transition = Transition(
            obs=runner.obs,
            action=action,
            log_prob=log_prob,
            value=value,
            next_value=next_value,
            reward=reward,
            terminated=terminated.astype(jnp.float32),
            done=done.astype(jnp.float32),
            solved=info["solved"],
        )
        episode_return = runner.episode_return + reward
        finished_return = jnp.where(done, episode_return, 0.0)
        runner = runner.replace(
            env_state=env_state, obs=obs, key=key, episode_return=jnp.where(done, 0.0, episode_return)
        )
        return runner, (transition, finished_return)

    runner, (transitions, finished_return) = jax.lax.scan(env_step, runner, None, length=num_steps)
    return runner, transitions, finished_return


def learn(
    runner: Runner, transitions: Transition, advantages, targets, *, network: nn.Module, settings: PPOSettings
) -> tuple[Runner, dict]:
    """`update_epochs` passes of `num_minibatches` Adam steps on the clipped PPO loss over the rollout. Returns
    the runner with new parameters, optimiser state and key, and the losses (update_epochs, num_minibatches)."""
    optimizer = make_optimizer(settings)
    batch_size = settings.batch_size
    ent_coef = entropy_weight(settings, runner.update)

    def update_minibatch(train, minibatch):
        params, opt_state = train
        batch, advantages, targets = minibatch
        grad_fn = jax.value_and_grad(ppo_loss, argnums=1, has_aux=True)
        (loss, parts), grads = grad_fn(network.apply, params, batch, advantages, targets, settings, ent_coef)
        updates, opt_state = optimizer.update(grads, opt_state, params)
        return (optax.apply_updates(params, updates), opt_state), dict(parts, loss=loss)

    def update_epoch(carry, _):
        params, opt_state, key, data = carry
        key, k_perm = jax.random.split(key)
        order = jax.random.permutation(k_perm, batch_size)
        shuffled = jax.tree.map(lambda x: x.reshape((batch_size,) + x.shape[2:])[order], data)
        minibatches = jax.tree.map(lambda x: x.reshape((settings.num_minibatches, -1) + x.shape[1:]), shuffled)
        minibatches = batch_sharded(minibatches, axis=1)  # each device computes its share of every minibatch
        (params, opt_state), losses = jax.lax.scan(update_minibatch, (params, opt_state), minibatches)
        return (params, opt_state, key, data), losses

    key, k_epochs = jax.random.split(runner.key)
    carry = (runner.params, runner.opt_state, k_epochs, (transitions, advantages, targets))
    (params, opt_state, _, _), losses = jax.lax.scan(update_epoch, carry, None, length=settings.update_epochs)
    return runner.replace(params=params, opt_state=opt_state, key=key), losses


def rollout_metrics(transitions: Transition, finished_return: jax.Array, losses: dict) -> dict:
    """The update's scalars: episodes ended, their mean return and solve rate, and the mean of each loss."""
    episodes = transitions.done.sum()
    return {
        "episodes": episodes,
        "return": finished_return.sum() / jnp.maximum(episodes, 1.0),
        "solve_rate": transitions.solved.sum() / jnp.maximum(episodes, 1.0),
        **jax.tree.map(jnp.mean, losses),
    }


@functools.partial(jax.jit, static_argnames=("env", "network", "settings", "fresh", "buffer_share"))
def ppo_update(
    runner: Runner,
    env_params: EnvParams,
    levels: Level | None,
    *,
    env: KinetixEnv,
    network: nn.Module,
    settings: PPOSettings,
    fresh: FreshLevels | None = None,
    buffer_share: float = 0.0,
) -> tuple[Runner, dict]:
    """One PPO update (DR and SFL): collect `num_steps` steps in every env, GAE, then `update_epochs` passes of
    `num_minibatches` minibatches. Returns the new runner and the update's metrics (scalars).

    Episodes restart from `levels` (or from fresh levels sampled for this update, with `fresh`), and a
    `buffer_share` of them from the runner's level buffer (`update_levels`)."""
    runner, levels = update_levels(runner, env, levels, fresh, buffer_share, settings.num_envs)
    restart = lambda key: draw_levels(levels, key, settings.num_envs)  # noqa: E731
    # --- collect
    runner, transitions, finished_return = collect(
        runner, env_params, restart, env=env, network=network, num_steps=settings.num_steps
    )
    # --- GAE
    advantages, targets = gae(transitions, settings.gamma, settings.gae_lambda)
    # --- update epochs
    runner, losses = learn(runner, transitions, advantages, targets, network=network, settings=settings)
    runner = runner.replace(update=runner.update + 1).placed()
    return runner, rollout_metrics(transitions, finished_return, losses)


@functools.partial(jax.jit, static_argnames=("env", "network", "settings", "fresh", "curriculum"))
def plr_update(
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
    """One update of robust PLR or ACCEL (`rl.curricula.plr`): every environment is reset to a level of its own
    and replays it whenever an episode ends. A replay update (once the buffer is `min_fill` full) plays buffer
    levels sampled by `plr.replay_probabilities`, trains on them as `ppo_update` does and rescores them; the other
    updates play candidates without training (new levels from the source, `fresh` or draws from `levels`; with
    ACCEL also `edits`-fold mutations of buffer levels), and the buffer keeps the best-scoring of its levels and
    these. PLR replays with probability `replay_prob`; ACCEL, which follows each replay with a mutation round,
    picks replay, mutation and new levels with probabilities p, p and 1 - p over 1 + p.
    Metrics: those of `ppo_update` (losses 0 when nothing was trained), `replay` and `mutate` (1 or 0)."""
    n = settings.num_envs
    buffer = runner.buffer
    key, k_mode, k_new, k_replay, k_mutate = jax.random.split(runner.key, 5)
    ready = buffer.size >= jnp.maximum(1, round(curriculum.min_fill * buffer.score.shape[0]))
    u, p = jax.random.uniform(k_mode), curriculum.replay_prob
    accel = curriculum.name == "accel"
    replay = ready & (u < (p / (1.0 + p) if accel else p))
    mutate = ready & ~replay & (u < 2.0 * p / (1.0 + p)) if accel else jnp.zeros((), bool)
    slots = plr.sample_replay(buffer, k_replay, n, runner.update, curriculum)
    buffered = index_level(buffer.levels, slots)
    new = lambda: fresh(k_new, n) if fresh is not None else draw_levels(levels, k_new, n)  # noqa: E731
    candidates = jax.lax.cond(replay, lambda: buffered, new)  # a replay round samples no new levels
    if accel:
        edit = functools.partial(mutate_level, env.static, edits=curriculum.edits)
        mutate_all = lambda: jax.vmap(edit)(jax.random.split(k_mutate, n), buffered)  # noqa: E731
        mutated = jax.lax.cond(mutate, mutate_all, lambda: buffered)  # the edits only run in mutation rounds
        candidates = jax.tree.map(lambda m, c: jnp.where(mutate, m, c), mutated, candidates)
    played = batch_sharded(jax.tree.map(lambda b, c: jnp.where(replay, b, c), buffered, candidates))
    obs, env_state = jax.vmap(env.reset_to_level)(played)
    runner = runner.replace(key=key, obs=obs, env_state=env_state, episode_return=jnp.zeros(n, jnp.float32))
    # --- collect: every environment stays on its level
    runner, transitions, finished_return = collect(
        runner, env_params, lambda _: played, env=env, network=network, num_steps=settings.num_steps
    )
    # --- GAE and the levels' scores
    advantages, targets = gae(transitions, settings.gamma, settings.gae_lambda)
    best_before = jnp.where(replay, buffer.max_return[slots], -jnp.inf)
    score, solve_rate, best = plr.level_scores(
        transitions.value, advantages, finished_return, transitions.done, transitions.solved, best_before, curriculum
    )
    # --- train on replayed levels only
    train = lambda r: learn(r, transitions, advantages, targets, network=network, settings=settings)  # noqa: E731
    skipped = jax.tree.map(lambda x: jnp.zeros(x.shape, x.dtype), jax.eval_shape(train, runner)[1])
    runner, losses = jax.lax.cond(replay, train, lambda r: (r, skipped), runner)
    buffer = jax.lax.cond(
        replay,
        lambda b: plr.rescore(b, slots, score, solve_rate, best, runner.update),
        lambda b: plr.insert(b, candidates, score, solve_rate, best, runner.update),
        buffer,
    )
    runner = runner.replace(buffer=buffer, update=runner.update + 1).placed()
    modes = {"replay": replay.astype(jnp.float32), "mutate": mutate.astype(jnp.float32)}
    return runner, rollout_metrics(transitions, finished_return, losses) | modes
