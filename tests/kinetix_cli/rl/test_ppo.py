"""PPO pieces with hand-worked numbers: GAE with terminations and truncations, the clipped losses, and the
symmetry loss."""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import optax
import pytest

from engine import SIZES
from kinetix_cli.bench.env import random_levels
from kinetix_cli.config import ConfigError, EnvSettings, ExperimentConfig, ModelSettings, PPOSettings
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.level import draw_levels, index_level
from kinetix_cli.env.mirror import MirrorPairEnv
from kinetix_cli.rl.distributions import kl_divergence, mirrored
from kinetix_cli.rl.networks import FirstViewNetwork, make_network
from kinetix_cli.rl.ppo import (
    Runner,
    Transition,
    collect,
    entropy_weight,
    first_reset,
    gae,
    ppo_loss,
    truncated_rows,
)


def _transitions(terminated, done):
    column = lambda xs: jnp.asarray(xs, jnp.float32)[:, None]  # noqa: E731  (num_steps, 1 env)
    zeros = column([0.0, 0.0, 0.0])
    return Transition(
        obs=zeros,
        action=zeros,
        log_prob=zeros,
        value=column([0.5, 0.2, 0.1]),
        next_value=column([0.2, 0.1, 0.3]),
        reward=column([1.0, 0.0, 2.0]),
        terminated=column(terminated),
        done=column(done),
        solved=zeros,
    )


def test_gae_stops_at_a_termination():
    # gamma = lambda = 0.5. t=2: delta = 2 - 0.1 = 1.9 (terminated: no bootstrap);
    # t=1: delta = 0 + 0.5 * 0.1 - 0.2 = -0.15, A = -0.15 + 0.25 * 1.9 = 0.325;
    # t=0: delta = 1 + 0.5 * 0.2 - 0.5 = 0.6, A = 0.6 + 0.25 * 0.325 = 0.68125.
    advantages, targets = gae(_transitions([0, 0, 1], [0, 0, 1]), 0.5, 0.5)
    np.testing.assert_allclose(advantages[:, 0], [0.68125, 0.325, 1.9], rtol=1e-6, atol=1e-6)  # [return]
    np.testing.assert_allclose(targets[:, 0], [1.18125, 0.525, 2.0], rtol=1e-6, atol=1e-6)  # [return]


def test_gae_bootstraps_a_truncated_episode():
    # t=2 truncated: delta = 2 + 0.5 * 0.3 - 0.1 = 2.05 (bootstrapped); the trace still stops there.
    advantages, _ = gae(_transitions([0, 0, 0], [0, 0, 1]), 0.5, 0.5)
    np.testing.assert_allclose(advantages[:, 0], [0.690625, 0.3625, 2.05], rtol=1e-6, atol=1e-6)  # [return]


def test_gae_does_not_leak_across_episodes():
    # An episode ends at t=1 (done); A_1 must not see A_2.
    advantages, _ = gae(_transitions([0, 1, 0], [0, 1, 0]), 0.5, 0.5)
    assert advantages[1, 0] == pytest.approx(0.0 - 0.2, abs=1e-6)  # [return]


class _FixedDist:
    def __init__(self, log_prob, entropy):
        self._log_prob, self._entropy = log_prob, entropy

    def log_prob(self, action):
        return self._log_prob

    def entropy(self):
        return self._entropy


def test_clipped_losses_by_hand():
    hp = PPOSettings(
        num_envs=1,
        num_steps=2,
        num_minibatches=1,
        clip_eps=0.2,
        ent_coef=0.01,
        vf_coef=0.5,
        total_timesteps=2,
        normalise_advantages=False,
    )
    batch = Transition(
        obs=jnp.zeros(2),
        action=jnp.zeros(2),
        log_prob=jnp.log(jnp.array([0.5, 0.5])),
        value=jnp.array([1.0, 1.0]),
        next_value=jnp.zeros(2),
        reward=jnp.zeros(2),
        terminated=jnp.zeros(2),
        done=jnp.zeros(2),
        solved=jnp.zeros(2),
    )
    # new probabilities 0.8 and 0.2: ratios 1.6 and 0.4, clipped to 1.2 and 0.8.
    new = _FixedDist(jnp.log(jnp.array([0.8, 0.2])), jnp.array([1.0, 1.0]))
    apply_fn = lambda params, obs: (new, jnp.array([2.0, 0.5]))  # noqa: E731
    advantages, targets = jnp.array([1.0, -1.0]), jnp.array([1.5, 1.5])
    total, parts = ppo_loss(apply_fn, None, batch, advantages, targets, hp, entropy_weight(hp, jnp.asarray(0)))
    # policy: -mean(min(1.6 * 1, 1.2 * 1), min(0.4 * -1, 0.8 * -1)) = -mean(1.2, -0.8) = -0.2
    assert float(parts["policy_loss"]) == pytest.approx(-0.2, rel=1e-5, abs=1e-6)  # [return]: ratio x advantage
    # value: clipped values 1.2 and 0.8; losses max((2-1.5)^2, (1.2-1.5)^2) = 0.25, max(1, 0.49) = 1 -> 0.5 * 0.625
    assert float(parts["value_loss"]) == pytest.approx(0.3125, rel=1e-5, abs=1e-6)  # [return^2]
    assert float(total) == pytest.approx(-0.2 + 0.5 * 0.3125 - 0.01 * 1.0, rel=1e-5, abs=1e-6)  # [loss]


@pytest.mark.slow  # ~21 s: the loss on observation pairs compiles and trains; make test keeps its exact value above
def test_the_symmetry_loss_compares_each_state_with_its_mirror_image_and_can_be_learned():
    """`ppo.mirror_coef`: the loss adds mirror_coef x the mean KL between the policy at each state and its choice at
    the mirror image, mirrored back (nonzero for a fresh network), over `mirror_share` of the minibatch, and Adam
    steps on it bring it down."""
    env_settings = EnvSettings(size="s", observation="symbolic-entity")
    base = make_network(ModelSettings(name="rel-mlp", width=16, actor_critic_layers=2), env_settings)
    network = FirstViewNetwork(base)
    env = MirrorPairEnv.of(KinetixEnv(SIZES["s"], observation="symbolic-entity"))
    levels = random_levels(SIZES["s"], 4, 0)
    pairs = jax.jit(jax.vmap(lambda i: env.observe(env.initial_state(index_level(levels, i)))))(jnp.arange(4))
    params = jax.tree.map(lambda x: x * 8.0, jax.jit(network.init)(jax.random.key(0), pairs))  # far from uniform
    dist, value = jax.jit(network.apply)(params, pairs)
    batch = Transition(
        obs=pairs,
        action=dist.mode(),
        log_prob=dist.log_prob(dist.mode()),
        value=value,
        next_value=value,
        reward=jnp.zeros(4),
        terminated=jnp.zeros(4),
        done=jnp.zeros(4),
        solved=jnp.zeros(4),
    )
    plain = PPOSettings(num_envs=4, num_steps=1, num_minibatches=1, total_timesteps=4)
    with_loss = dataclasses.replace(plain, mirror_coef=2.0)
    loss = jax.jit(ppo_loss, static_argnums=(0, 5))
    zeros = jnp.zeros(4)
    total, parts = loss(network.apply, params, batch, zeros, zeros, plain, 0.01)
    total_2, parts_2 = loss(network.apply, params, batch, zeros, zeros, with_loss, 0.01)
    twin = jax.jit(base.apply)(params, pairs[1])[0]
    expected = float(kl_divergence(dist, mirrored(twin)).mean())
    assert "mirror_loss" not in parts and expected > 0.01, expected
    np.testing.assert_allclose(float(parts_2["mirror_loss"]), expected, atol=1e-6)  # [nats]
    np.testing.assert_allclose(float(total_2), float(total) + 2.0 * expected, atol=1e-5)  # [loss]
    half = loss(network.apply, params, batch, zeros, zeros, dataclasses.replace(with_loss, mirror_share=0.5), 0.01)
    on_two = jax.tree.map(lambda x: x[:2], (dist, twin))
    np.testing.assert_allclose(
        float(half[1]["mirror_loss"]), float(kl_divergence(on_two[0], mirrored(on_two[1])).mean()), atol=1e-6
    )  # [nats]: the first half of the (shuffled) minibatch
    optimizer = optax.adam(1e-3)

    @jax.jit
    def descend(params, opt_state):
        grads = jax.grad(lambda p: loss(network.apply, p, batch, zeros, zeros, with_loss, 0.0)[1]["mirror_loss"])
        updates, opt_state = optimizer.update(grads(params), opt_state)
        return optax.apply_updates(params, updates), opt_state

    trained, opt_state = params, optimizer.init(params)
    for _ in range(20):
        trained, opt_state = descend(trained, opt_state)
    after = float(loss(network.apply, trained, batch, zeros, zeros, with_loss, 0.0)[1]["mirror_loss"])
    assert after < 0.5 * expected, (after, expected)
    with pytest.raises(ConfigError, match="ppo.mirror_coef: model.mirror 'geometric' is left-right equivariant"):
        ExperimentConfig(env=env_settings, model=ModelSettings(name="rel-mlp", mirror="geometric"), ppo=with_loss)
    with pytest.raises(ConfigError, match="ppo.mirror_coef"):
        dataclasses.replace(plain, mirror_coef=-1.0)
    with pytest.raises(ConfigError, match="ppo.mirror_share"):
        dataclasses.replace(plain, mirror_share=0.0)


def test_the_entropy_weight_moves_from_ent_coef_to_ent_coef_end_over_the_run():
    constant = PPOSettings(num_envs=2, num_steps=2, num_minibatches=1, total_timesteps=44, ent_coef=0.05)  # 11 updates
    assert entropy_weight(constant, jnp.asarray(7)) == 0.05
    decaying = dataclasses.replace(constant, ent_coef_end=0.01)
    weights = [float(entropy_weight(decaying, jnp.asarray(u))) for u in (0, 5, 10, 12)]
    assert weights == pytest.approx([0.05, 0.03, 0.01, 0.01], abs=1e-8)  # [loss weight]: float32 ulp of 0.05 is 4e-9


draw = jax.jit(draw_levels, static_argnums=2)  # op by op, each of a level's ~50 arrays is its own small compile


def test_the_first_reset_happens_at_update_0_only():
    """A fresh source's environments start on a placeholder: update 0 resets them all to pool levels (the
    environments then hold exactly the levels `draw_levels` picks); any later update leaves them as they are."""
    static = SIZES["s"]
    env = KinetixEnv(static, observation="symbolic-flat")
    levels = random_levels(static, 4, 0)
    start_obs, start_state = jax.vmap(env.reset_to_level)(index_level(levels, np.zeros(3, np.int32)))
    pool, key = index_level(levels, np.arange(1, 4)), jax.random.key(5)

    @jax.jit
    def reset(update):
        runner = Runner(None, None, start_state, start_obs, jnp.zeros(3), jax.random.key(0), update)
        return first_reset(runner, env, pool, key).obs

    expected, _ = jax.vmap(env.reset_to_level)(draw(pool, key, 3))
    np.testing.assert_array_equal(reset(jnp.int32(0)), expected)
    assert not np.array_equal(expected, start_obs)
    np.testing.assert_array_equal(reset(jnp.int32(1)), start_obs)


def test_one_pass_per_step_gives_the_two_pass_rollouts_transitions():
    """`collect` takes each step's bootstrap value from the next step's pass, and truncated episodes' from a pass on
    their final observations alone: the transitions of the plain rollout that passes every final observation
    through the network. Episodes are staggered so that some steps truncate more environments than the small pass
    holds (all rows then) and others fewer (just those rows)."""
    envs, steps = 32, 6  # the small pass: 2 rows (`truncated_rows`)
    env = KinetixEnv(SIZES["s"], observation="symbolic-flat")
    env_params = EnvParams(max_steps=16)
    network = make_network(
        ModelSettings(name="flat-mlp", width=16, actor_critic_layers=1), EnvSettings(observation="symbolic-flat")
    )
    pool = random_levels(SIZES["s"], 4, 0)
    obs, state = jax.vmap(env.reset_to_level)(draw(pool, jax.random.key(1), envs))
    slot = jnp.arange(envs)
    state = state.replace(steps=jnp.where(slot < 8, 15, slot % 16).astype(jnp.int32))  # step 1: 10 truncated, then 2
    params = jax.jit(network.init)(jax.random.key(2), obs)
    runner = Runner(params, None, state, obs, jnp.zeros(envs), jax.random.key(3), jnp.int32(0))
    restart = lambda key: draw_levels(pool, key, envs)  # noqa: E731
    step = jax.vmap(env.step, in_axes=(0, 0, None, 0))

    def two_passes(runner):
        def body(runner, _):
            key, k_act, k_reset = jax.random.split(runner.key, 3)
            dist, value = network.apply(runner.params, runner.obs)
            action = dist.sample(k_act)
            obs, state, _, _, truncated, info = step(runner.env_state, action, env_params, restart(k_reset))
            _, next_value = network.apply(runner.params, info["final_observation"])
            return runner.replace(env_state=state, obs=obs, key=key), (action, value, next_value, truncated)

        return jax.lax.scan(body, runner, None, length=steps)[1]

    one = jax.jit(lambda r: collect(r, env_params, restart, env=env, network=network, num_steps=steps)[1])(runner)
    action, value, next_value, truncated = jax.jit(two_passes)(runner)
    counts = np.asarray(truncated).sum(axis=1)
    assert counts.max() > truncated_rows(envs) >= counts[1:].max() > 0, counts
    np.testing.assert_array_equal(one.action, action)
    np.testing.assert_allclose(one.value, value, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(one.next_value, next_value, rtol=1e-6, atol=1e-6)
