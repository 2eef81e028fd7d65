"""PPO on Kinetix through its gymnax interface, in one file: the way a PureJaxRL-style training loop uses it.

    python examples/gymnax_ppo.py --levels s --updates 200
    python examples/gymnax_ppo.py --levels fresh --size s --num-envs 256

The environment comes from `kinetix_cli.gym.make` and is used only through gymnax's API (`reset`, `step`, the
spaces, `default_params`) and `refresh_levels`; nothing else of the toolkit is imported. The policy is an MLP on the
flat observation with one categorical distribution per multi-discrete action entry. Each update collects
`num_steps` steps of `num_envs` environments with `jax.lax.scan`, computes GAE advantages and runs a few epochs of
clipped PPO on minibatches; with `--levels fresh` it then draws a new batch of fresh levels once as many episodes
have started as a batch holds. The whole update is one jitted function.
"""

from __future__ import annotations

import argparse
import time
from typing import NamedTuple

import flax.linen as nn
import jax
import jax.numpy as jnp
import numpy as np
import optax

from kinetix_cli.gym import make


class Batch(NamedTuple):
    obs: jax.Array
    action: jax.Array
    log_prob: jax.Array
    value: jax.Array
    reward: jax.Array
    done: jax.Array
    bootstrap: jax.Array  # value of the observation a truncated episode ended on (0 elsewhere)
    solved: jax.Array


class ActorCritic(nn.Module):
    """Logits for each action entry (entries with fewer choices mask the rest) and a value."""

    nvec: tuple[int, ...]
    width: int = 128

    @nn.compact
    def __call__(self, obs):
        def trunk(x):
            for _ in range(2):
                x = nn.tanh(nn.Dense(self.width)(x))
            return x

        most = max(self.nvec)
        logits = nn.Dense(len(self.nvec) * most, kernel_init=nn.initializers.orthogonal(0.01))(trunk(obs))
        logits = logits.reshape(*obs.shape[:-1], len(self.nvec), most)
        logits = jnp.where(jnp.arange(most) < jnp.asarray(self.nvec)[:, None], logits, -1e9)
        value = nn.Dense(1, kernel_init=nn.initializers.orthogonal(1.0))(trunk(obs))[..., 0]
        return logits, value


def log_prob(logits, action):
    chosen = jnp.take_along_axis(jax.nn.log_softmax(logits), action[..., None], axis=-1)[..., 0]
    return chosen.sum(-1)


def entropy(logits):
    p = jax.nn.softmax(logits)
    return -(p * jax.nn.log_softmax(logits)).sum((-1, -2))


def train(args: argparse.Namespace) -> list[dict]:
    env, env_params = make(args.levels, size=args.size)
    nvec = tuple(int(n) for n in env.action_space(env_params).nvec)
    network = ActorCritic(nvec)
    obs_shape = env.observation_space(env_params).shape
    key = jax.random.key(args.seed)
    key, init_key, reset_key = jax.random.split(key, 3)
    params = network.init(init_key, jnp.zeros(obs_shape))
    minibatch = args.num_envs * args.num_steps // args.minibatches
    optimiser = optax.chain(optax.clip_by_global_norm(0.5), optax.adam(args.lr, eps=1e-5))
    opt_state = optimiser.init(params)
    obs, state = jax.vmap(env.reset, in_axes=(0, None))(jax.random.split(reset_key, args.num_envs), env_params)
    started = jnp.int32(args.num_envs)  # episodes started on the current batch of levels

    def rollout_step(carry, key, env_params):
        params, obs, state = carry
        act_key, step_key = jax.random.split(key)
        logits, value = network.apply(params, obs)
        action = jax.random.categorical(act_key, logits).astype(jnp.int32)
        keys = jax.random.split(step_key, args.num_envs)
        next_obs, state, reward, terminated, truncated, info = jax.vmap(env.step, in_axes=(0, 0, 0, None))(
            keys, state, action, env_params
        )
        _, final_value = network.apply(params, info["final_observation"])
        step = Batch(
            obs=obs,
            action=action,
            log_prob=log_prob(logits, action),
            value=value,
            reward=reward,
            done=terminated | truncated,
            bootstrap=jnp.where(truncated, final_value, 0.0),
            solved=info["solved"],
        )
        return (params, next_obs, state), step

    def advantages(batch: Batch, last_value):
        def back(carry, step):
            gae, next_value = carry
            reward, value, done, bootstrap = step
            next_value = jnp.where(done, bootstrap, next_value)
            delta = reward + args.gamma * next_value - value
            gae = delta + args.gamma * args.gae_lambda * jnp.where(done, 0.0, gae)
            return (gae, value), gae

        steps = (batch.reward, batch.value, batch.done, batch.bootstrap)
        _, gae = jax.lax.scan(back, (jnp.zeros_like(last_value), last_value), steps, reverse=True)
        return gae, gae + batch.value

    def loss(params, batch: Batch, advantage, target):
        logits, value = network.apply(params, batch.obs)
        ratio = jnp.exp(log_prob(logits, batch.action) - batch.log_prob)
        advantage = (advantage - advantage.mean()) / (advantage.std() + 1e-8)
        clipped = jnp.clip(ratio, 1 - args.clip, 1 + args.clip)
        policy_loss = -jnp.minimum(ratio * advantage, clipped * advantage).mean()
        value_loss = 0.5 * ((value - target) ** 2).mean()
        return policy_loss + 0.5 * value_loss - args.ent_coef * entropy(logits).mean()

    @jax.jit
    def update(params, opt_state, obs, state, env_params, started, key):
        key, rollout_key, level_key = jax.random.split(key, 3)
        (params, obs, state), batch = jax.lax.scan(
            lambda carry, key: rollout_step(carry, key, env_params),
            (params, obs, state),
            jax.random.split(rollout_key, args.num_steps),
        )
        _, last_value = network.apply(params, obs)
        advantage, target = advantages(batch, last_value)
        flat = jax.tree.map(lambda x: x.reshape(-1, *x.shape[2:]), (batch, advantage, target))

        def epoch(carry, key):
            params, opt_state = carry
            order = jax.random.permutation(key, args.num_envs * args.num_steps)
            shuffled = jax.tree.map(lambda x: x[order].reshape(args.minibatches, minibatch, *x.shape[1:]), flat)

            def minibatch_step(carry, data):
                params, opt_state = carry
                grads = jax.grad(loss)(params, *data)
                changes, opt_state = optimiser.update(grads, opt_state)
                return (optax.apply_updates(params, changes), opt_state), None

            return jax.lax.scan(minibatch_step, (params, opt_state), shuffled)[0], None

        (params, opt_state), _ = jax.lax.scan(epoch, (params, opt_state), jax.random.split(key, args.epochs))

        # fresh levels: a new batch once as many episodes have started as it holds (a level pool keeps its levels)
        ended = batch.done.sum()
        started = started + ended
        due = started >= env_params.pool_count
        env_params = jax.lax.cond(due, env.refresh_levels, lambda _, p: p, level_key, env_params)
        started = jnp.where(due, 0, started)
        stats = {"episodes": ended, "solved": batch.solved.sum(), "reward": batch.reward.sum() / args.num_envs}
        return params, opt_state, obs, state, env_params, started, stats

    history = []
    for i in range(args.updates):
        start = time.perf_counter()
        key, update_key = jax.random.split(key)
        params, opt_state, obs, state, env_params, started, stats = update(
            params, opt_state, obs, state, env_params, started, update_key
        )
        stats = {k: float(v) for k, v in stats.items()}
        stats["solve_rate"] = stats["solved"] / max(stats["episodes"], 1.0)
        stats["seconds"] = time.perf_counter() - start
        history.append(stats)
        if i % args.print_every == 0 or i == args.updates - 1:
            print(
                f"update {i + 1}/{args.updates}: {int(stats['episodes'])} episodes ended, "
                f"solved {100 * stats['solve_rate']:.0f}%, reward per env {stats['reward']:+.3f}"
            )
    return history


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default="s", help="'fresh', a suite (s, m, l), level files or a folder")
    parser.add_argument("--size", default=None, help="s, m or l (default: what the levels need; m for fresh)")
    parser.add_argument("--num-envs", type=int, default=64)
    parser.add_argument("--num-steps", type=int, default=64)
    parser.add_argument("--updates", type=int, default=100)
    parser.add_argument("--minibatches", type=int, default=4)
    parser.add_argument("--epochs", type=int, default=4)
    parser.add_argument("--lr", type=float, default=3e-4)
    parser.add_argument("--gamma", type=float, default=0.995)
    parser.add_argument("--gae-lambda", type=float, default=0.9)
    parser.add_argument("--clip", type=float, default=0.2)
    parser.add_argument("--ent-coef", type=float, default=0.01)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--print-every", type=int, default=10)
    args = parser.parse_args(argv)
    if args.num_envs * args.num_steps % args.minibatches:
        parser.error("--num-envs x --num-steps must divide into --minibatches")
    history = train(args)
    steps = args.updates * args.num_envs * args.num_steps
    print(f"{steps:,} env steps in {sum(h['seconds'] for h in history):.1f} s (first update includes compiling)")
    print(f"mean solve rate over the last updates: {100 * np.mean([h['solve_rate'] for h in history[-10:]]):.1f}%")


if __name__ == "__main__":
    main()
