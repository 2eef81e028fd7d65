"""PPO, the PureJaxRL way: rollout, GAE and the update epochs in one jitted function over vmapped environments.

`make_update(...)` returns `update(runner) -> (runner, metrics)`: one PPO update of `num_envs x num_steps`
environment steps. The caller loops over updates (checkpoints, logging and resume live outside the jit).

Timeouts: an episode that hits the step cap is *truncated*, not terminated. Its last transition bootstraps
from the value of the final observation (computed before the auto-reset), so the cap does not look like a
failure to the critic. Every transition stores `next_value` = V(observation after the step, before any reset);
the GAE recursion stops at every episode boundary, and only true terminations (green touched blue or red,
NaN) zero the bootstrap.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import optax
from flax import struct

from kinetix_cli.env import EnvParams, KinetixEnv


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
    """The scan carry between updates: everything needed to continue training bit for bit.

    Attributes:
        params: network parameters.
        opt_state: optimiser state.
        env_state: batched environment state (num_envs, ...).
        obs: the current batched observation.
        episode_return: (num_envs,) return of the running episodes.
        key: PRNG key.
        update: () int32 updates done.
    """

    params: Any
    opt_state: Any
    env_state: Any
    obs: Any
    episode_return: jax.Array
    key: jax.Array
    update: jax.Array


class PPOHyper(NamedTuple):
    """The PPO numbers `make_update` needs (see `kinetix_cli.config.PPOSettings` for meanings)."""

    num_envs: int
    num_steps: int
    update_epochs: int
    num_minibatches: int
    gamma: float
    gae_lambda: float
    clip_eps: float
    ent_coef: float
    vf_coef: float
    normalise_advantages: bool = True


def make_optimizer(lr, max_grad_norm: float, adam_eps: float) -> optax.GradientTransformation:
    """Adam with global-norm gradient clipping; `lr` a float or an optax schedule."""
    return optax.chain(optax.clip_by_global_norm(max_grad_norm), optax.adam(lr, eps=adam_eps))


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


def ppo_loss(apply_fn, params, batch: Transition, advantages, targets, hp: PPOHyper):
    """Clipped policy loss + vf_coef * clipped value loss - ent_coef * entropy, and its parts."""
    dist, value = apply_fn(params, batch.obs)
    log_prob = dist.log_prob(batch.action)
    if hp.normalise_advantages:
        advantages = (advantages - advantages.mean()) / (advantages.std() + 1e-8)
    ratio = jnp.exp(log_prob - batch.log_prob)
    clipped_ratio = jnp.clip(ratio, 1.0 - hp.clip_eps, 1.0 + hp.clip_eps)
    policy_loss = -jnp.minimum(ratio * advantages, clipped_ratio * advantages).mean()
    value_clipped = batch.value + jnp.clip(value - batch.value, -hp.clip_eps, hp.clip_eps)
    value_loss = 0.5 * jnp.maximum((value - targets) ** 2, (value_clipped - targets) ** 2).mean()
    entropy = dist.entropy().mean()
    total = policy_loss + hp.vf_coef * value_loss - hp.ent_coef * entropy
    approx_kl = ((ratio - 1.0) - jnp.log(ratio)).mean()
    return total, {"policy_loss": policy_loss, "value_loss": value_loss, "entropy": entropy, "approx_kl": approx_kl}


def make_update(env: KinetixEnv, env_params: EnvParams, apply_fn, optimizer, hp: PPOHyper):
    """The jitted PPO update `update(runner) -> (runner, metrics)`; `apply_fn(params, obs) -> (dist, value)`
    works on a leading batch axis."""
    batch_size = hp.num_envs * hp.num_steps
    if batch_size % hp.num_minibatches:
        raise ValueError(f"num_envs * num_steps = {batch_size} must be divisible by num_minibatches")

    def env_step(runner: Runner, _):
        # --- act
        key, k_act, k_env = jax.random.split(runner.key, 3)
        dist, value = apply_fn(runner.params, runner.obs)
        action = dist.sample(k_act)
        log_prob = dist.log_prob(action)
        # --- step without reset, then reset the finished episodes
        stepped, reward, done, info = jax.vmap(env.step_env, in_axes=(0, 0, None))(runner.env_state, action, env_params)
        final_obs = jax.vmap(env.observe)(stepped)
        _, next_value = apply_fn(runner.params, final_obs)
        reset_keys = jax.random.split(k_env, hp.num_envs)
        fresh = jax.vmap(lambda k: env.state_from_level(env.reset_fn(k)))(reset_keys)
        env_state = jax.tree.map(lambda f, s: _where_env(done, f, s), fresh, stepped)
        obs = jax.tree.map(lambda f, s: _where_env(done, f, s), jax.vmap(env.observe)(fresh), final_obs)
        terminated = done & ~info["truncated"]
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

    def update_minibatch(train, minibatch):
        params, opt_state = train
        batch, advantages, targets = minibatch
        grad_fn = jax.value_and_grad(ppo_loss, argnums=1, has_aux=True)
        (loss, parts), grads = grad_fn(apply_fn, params, batch, advantages, targets, hp)
        updates, opt_state = optimizer.update(grads, opt_state, params)
        return (optax.apply_updates(params, updates), opt_state), dict(parts, loss=loss)

    def update_epoch(carry, _):
        params, opt_state, key, data = carry
        key, k_perm = jax.random.split(key)
        order = jax.random.permutation(k_perm, batch_size)
        shuffled = jax.tree.map(lambda x: x.reshape((batch_size,) + x.shape[2:])[order], data)
        minibatches = jax.tree.map(lambda x: x.reshape((hp.num_minibatches, -1) + x.shape[1:]), shuffled)
        (params, opt_state), losses = jax.lax.scan(update_minibatch, (params, opt_state), minibatches)
        return (params, opt_state, key, data), losses

    def update(runner: Runner):
        # --- collect
        runner, (transitions, finished_return) = jax.lax.scan(env_step, runner, None, length=hp.num_steps)
        # --- GAE
        advantages, targets = gae(transitions, hp.gamma, hp.gae_lambda)
        # --- update epochs
        key, k_epochs = jax.random.split(runner.key)
        carry = (runner.params, runner.opt_state, k_epochs, (transitions, advantages, targets))
        (params, opt_state, _, _), losses = jax.lax.scan(update_epoch, carry, None, length=hp.update_epochs)
        runner = runner.replace(params=params, opt_state=opt_state, key=key, update=runner.update + 1)
        episodes = transitions.done.sum()
        metrics = {
            "episodes": episodes,
            "return": finished_return.sum() / jnp.maximum(episodes, 1.0),
            "solve_rate": transitions.solved.sum() / jnp.maximum(episodes, 1.0),
            **jax.tree.map(jnp.mean, losses),
        }
        return runner, metrics

    return jax.jit(update)


def _where_env(done: jax.Array, a: jax.Array, b: jax.Array) -> jax.Array:
    """Select per environment: `a` where `done` (num_envs,), else `b`, broadcasting over trailing axes."""
    return jnp.where(done.reshape(done.shape + (1,) * (a.ndim - 1)), a, b)


def init_runner(env: KinetixEnv, env_params: EnvParams, init_fn, optimizer, num_envs: int, key: jax.Array) -> Runner:
    """Fresh parameters, optimiser state and `num_envs` reset environments; `init_fn(key, obs) -> params`."""
    k_params, k_reset, key = jax.random.split(key, 3)
    obs, env_state = jax.vmap(env.reset, in_axes=(0, None))(jax.random.split(k_reset, num_envs), env_params)
    params = init_fn(k_params, obs)
    return Runner(
        params=params,
        opt_state=optimizer.init(params),
        env_state=env_state,
        obs=obs,
        episode_return=jnp.zeros(num_envs, jnp.float32),
        key=key,
        update=jnp.zeros((), jnp.int32),
    )
