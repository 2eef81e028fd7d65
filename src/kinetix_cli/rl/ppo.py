"""PPO, the PureJaxRL way: rollout, GAE and the update epochs in one jitted function over vmapped environments.

`ppo_update(runner, env_params, levels, env=..., network=..., settings=...)` is one PPO update of
`num_envs x num_steps` environment steps; the caller loops over updates (checkpoints, logging and resume live
outside the jit). The environment, the network and the `PPOSettings` section are static arguments (all three are
hashable by value), so every call with equal settings shares one compile; the level pool is an argument, so a new
pool of the same shape does not recompile either.

Episodes that end restart from a level drawn uniformly from the update's pool by the environment's own auto-reset
(`KinetixEnv.step`). The pool is `levels` (a fixed pool on the device: generated at the start, a level set, level
files) or, with the static `fresh` source (and `levels` None), a batch of `num_envs` new levels sampled at the
start of every update inside the jit (`kinetix_cli.generator.fresh`). Each curriculum (`rl.curricula`) has an
update of its own built from the same parts (`train_on`, or `collect`, `gae` and `learn`).

Timeouts: an episode that hits the step cap is *truncated*, not terminated. Its last
transition bootstraps from the value of the final observation (`info["final_observation"]`, before the reset),
so the cap does not look like a failure to the critic. The rollout makes one network pass per step, plus one on
just the truncated rows (`collect`). Every transition stores `next_value` = V(observation after
the step, before any reset); the GAE recursion stops at every episode boundary, and only true terminations (green
touched blue or red, NaN) zero the bootstrap.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import flax.linen as nn
import jax
import jax.numpy as jnp
import optax
from flax import struct

from kinetix_cli.config import PPOSettings
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.level import Level, draw_levels
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.parallel import COPY, SPLIT, batch_sharded, per_device, replicated
from kinetix_cli.rl.buffer import LevelBuffer, empty_buffer
from kinetix_cli.rl.distributions import kl_divergence, mirrored
from kinetix_cli.trace_cache import cached_jit


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
        buffer: the curriculum's level buffer (`rl.buffer.LevelBuffer`), or None (DR).
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
    """Clipped policy loss + vf_coef * clipped value loss - ent_coef * entropy (+ mirror_coef * the symmetry
    loss: the KL between the policy at each state and its choice at the mirror image, mirrored back, over the
    minibatch's first `mirror_batch` transitions), and its parts."""
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
    parts = {"policy_loss": policy_loss, "value_loss": value_loss, "entropy": entropy, "approx_kl": approx_kl}
    if settings.mirror_coef:  # the observations are (state, mirror image) pairs (`networks.FirstViewNetwork`)
        sample = lambda tree: jax.tree.map(lambda x: x[: settings.mirror_batch], tree)  # noqa: E731  (shuffled)
        twin, _ = apply_fn(params, (sample(batch.obs[1]), sample(batch.obs[0])))
        parts["mirror_loss"] = kl_divergence(sample(dist), mirrored(twin)).mean()
        total = total + settings.mirror_coef * parts["mirror_loss"]
    return total, parts


def first_reset(runner: Runner, env: KinetixEnv, pool: Level, key: jax.Array) -> Runner:
    """With a fresh level source `init_runner` starts every environment on an empty arena: at update 0, and only
    then, they all reset to levels drawn from the update's `pool` (later updates keep their environments).

    Every update computes the reset (about one environment step per environment, against `num_steps` of them
    in the rollout) and keeps it at update 0 only: a `lax.cond` here would hold the gathers of the drawn levels,
    which on a CPU split into devices can stall the run (`parallel.per_device`)."""
    count = runner.episode_return.shape[0]
    obs, env_state = jax.vmap(env.reset_to_level)(batch_sharded(draw_levels(pool, key, count)))
    first = runner.update == 0
    keep = lambda new, old: jnp.where(first, new, old)  # noqa: E731
    return runner.replace(
        obs=jax.tree.map(keep, obs, runner.obs), env_state=jax.tree.map(keep, env_state, runner.env_state)
    )


def update_keys(runner: Runner) -> tuple[Runner, jax.Array, jax.Array, jax.Array]:
    """The runner with its key advanced, and the update's keys for the source's levels, the curriculum's buffer
    draw and the first reset (one stream shared by `ppo_update` and SFL's update)."""
    key, k_source, k_buffer, k_first = jax.random.split(runner.key, 4)
    return runner.replace(key=key), k_source, k_buffer, k_first


@cached_jit(static_argnums=(0, 1, 2), static_argnames=("fresh", "buffer_size"))
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
    episodes that ended at each step (0 elsewhere).

    One network pass per step: the pass on a step's new observations gives the next step's policy and the value
    that bootstraps this step wherever its episode goes on (there the observation is the final one). Only a
    truncated episode bootstraps from an observation no pass sees (its final one, before the reset): those
    values come from a pass on just the truncated rows (`final_values`)."""
    step = jax.vmap(env.step, in_axes=(0, 0, None, 0))

    def env_step(carry, _):
        runner, dist, value = carry
        # --- act
        key, k_act, k_reset = jax.random.split(runner.key, 3)
        action = dist.sample(k_act)
        log_prob = dist.log_prob(action)
        # --- step; ended episodes restart
        obs, env_state, reward, terminated, truncated, info = step(
            runner.env_state, action, env_params, batch_sharded(restart(k_reset))
        )
        next_dist, next_obs_value = network.apply(runner.params, obs)
        final_value = final_values(network, runner.params, info["final_observation"], truncated)
        done = terminated | truncated
        transition = Transition(
            obs=runner.obs,
            action=action,
            log_prob=log_prob,
            value=value,
            next_value=jnp.where(truncated, final_value, next_obs_value),
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
        return (runner, next_dist, next_obs_value), (transition, finished_return)

    first = (runner, *network.apply(runner.params, runner.obs))
    (runner, _, _), (transitions, finished_return) = jax.lax.scan(env_step, first, None, length=num_steps)
    return runner, transitions, finished_return


TRUNCATED_SHARE = 16
"""`final_values` evaluates the truncated rows of a step as one pass on 1/16 of each device's environments (at
least one row) when they fit, else on all of them."""


def truncated_rows(num_envs: int) -> int:
    """Rows of the small pass of `final_values` for `num_envs` environments (on one device)."""
    return max(1, num_envs // TRUNCATED_SHARE)


def final_values(network: nn.Module, params, final_obs, truncated: jax.Array) -> jax.Array:
    """(envs,) the value of each truncated environment's final observation (other rows: any finite value).

    Truncations are few per step once episodes fall out of step (an episode is truncated only at the step cap),
    so when at most `truncated_rows` environments of a device were truncated, one pass on those rows (gathered;
    padding repeats the first) gives them; when more were, as in the first episodes of a run, whose environments
    start together, one pass on every row of the device does. Each device decides for its own environments
    (`parallel.per_device`), so the branch holds no collective."""

    def on_device(params, final_obs, truncated):
        rows = truncated_rows(truncated.shape[0])

        def few():
            index = jnp.nonzero(truncated, size=rows, fill_value=0)[0]
            _, value = network.apply(params, jax.tree.map(lambda x: x[index], final_obs))
            return jnp.zeros(truncated.shape, value.dtype).at[index].set(value)

        def every():
            return network.apply(params, final_obs)[1]

        return jax.lax.cond(jnp.sum(truncated) <= rows, few, every)

    return per_device(on_device, in_specs=(COPY, SPLIT, SPLIT))(params, final_obs, truncated)


LOSS_METRICS = ("loss", "policy_loss", "value_loss", "entropy", "approx_kl", "mirror_loss")  # what `learn` measures


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


def train_on(
    runner: Runner, env_params: EnvParams, pool: Level, *, env: KinetixEnv, network: nn.Module, settings: PPOSettings
) -> tuple[Runner, dict]:
    """Collect `num_steps` steps in every env (ended episodes restart from levels drawn uniformly from `pool`),
    GAE, then `update_epochs` passes of `num_minibatches` minibatches. Returns the new runner (one more update)
    and the update's metrics (scalars)."""
    restart = lambda key: draw_levels(pool, key, settings.num_envs)  # noqa: E731
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


@cached_jit(static_argnames=("env", "network", "settings", "fresh"))
def ppo_update(
    runner: Runner,
    env_params: EnvParams,
    levels: Level | None,
    *,
    env: KinetixEnv,
    network: nn.Module,
    settings: PPOSettings,
    fresh: FreshLevels | None = None,
) -> tuple[Runner, dict]:
    """One PPO update with domain randomisation: episodes restart from levels drawn uniformly from the pool
    `levels`, or with `fresh` (and `levels` None) from `num_envs` new levels sampled for this update
    (`train_on`). Returns the new runner and the update's metrics."""
    if fresh is not None:
        runner, k_source, _, k_first = update_keys(runner)
        levels = batch_sharded(fresh(k_source, settings.num_envs))
        runner = first_reset(runner, env, levels, k_first)
    return train_on(runner, env_params, levels, env=env, network=network, settings=settings)
