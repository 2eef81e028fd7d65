"""Networks and distributions: hand-worked distribution values, output shapes per model and action type on
real observations, masked rows and slot order that do not change the output, and size independence."""

from __future__ import annotations

import dataclasses
import functools
import math

import flax.linen as nn
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from engine import SIZES
from kinetix_cli.bench.env import random_levels
from kinetix_cli.config import ConfigError, EnvSettings, ExperimentConfig, ModelSettings, PPOSettings
from kinetix_cli.constants import ACTION_TYPES, MODEL_NAMES, MODEL_OBSERVATIONS, OBSERVATION_TYPES
from kinetix_cli.env.actions import sample_action
from kinetix_cli.env.environment import KinetixEnv
from kinetix_cli.env.level import index_level
from kinetix_cli.env.mirror import MirrorPairEnv, mirror_action, mirror_env_state
from kinetix_cli.env.observations import ARENA_SIDES, used_bindings
from kinetix_cli.rl.distributions import (
    Categorical,
    DiagGaussian,
    MultiCategorical,
    averaged,
    kl_divergence,
    mirrored,
)
from kinetix_cli.rl.networks import MIRROR_MODES, action_distribution, make_network, mirror_joined, parameter_count

NVEC = (3, 3, 3, 3, 2, 2)
BATCH = 3
ACTION_ENCODING = {"multi-discrete": ((6,), jnp.int32), "discrete": ((), jnp.int32), "continuous": ((6,), jnp.float32)}
MODEL_OBSERVATION_PAIRS = [(m, o) for m in MODEL_NAMES for o in MODEL_OBSERVATIONS[m]]
REFUSED_PAIRS = [(m, o) for m in MODEL_NAMES for o in OBSERVATION_TYPES if o not in MODEL_OBSERVATIONS[m]]


@functools.cache
def observations(size: str, observation: str):
    """(BATCH,) batched reset observations of random levels of `size`."""
    static = SIZES[size]
    env = KinetixEnv(static, observation=observation)
    levels = random_levels(static, 4, 0)
    return jax.jit(jax.vmap(lambda i: env.reset_to_level(index_level(levels, i))[0]))(jnp.arange(BATCH))


def tiny(model: str, action_type: str = "multi-discrete", observation: str | None = None):
    settings = ModelSettings(name=model, width=16, actor_critic_layers=2, heads=4)
    env = EnvSettings(size="s", observation=observation or MODEL_OBSERVATIONS[model][0], action=action_type)
    return make_network(settings, env)


# --- distributions ---------------------------------------------------------------------------------------
def test_categorical_by_hand():
    uniform = Categorical(jnp.zeros(3))
    np.testing.assert_allclose(uniform.entropy(), math.log(3), rtol=1e-6, atol=1e-6)  # [nats]
    np.testing.assert_allclose(uniform.log_prob(jnp.int32(2)), -math.log(3), rtol=1e-6, atol=1e-6)  # [nats]
    skewed = Categorical(jnp.log(jnp.array([0.5, 0.25, 0.25])))
    np.testing.assert_allclose(skewed.entropy(), 1.5 * math.log(2), rtol=1e-6, atol=1e-6)  # [nats]
    expected = [math.log(0.5), math.log(0.25)]
    np.testing.assert_allclose(skewed.log_prob(jnp.array([0, 1])), expected, rtol=1e-6, atol=1e-6)  # [nats]
    assert skewed.mode() == 0 and skewed.mode().dtype == jnp.int32
    samples = jax.vmap(skewed.sample)(jax.random.split(jax.random.key(0), 4000))
    np.testing.assert_allclose(np.bincount(np.asarray(samples), minlength=3) / 4000, [0.5, 0.25, 0.25], atol=0.03)


def test_multi_categorical_masks_padding():
    dist = MultiCategorical.from_flat(jnp.zeros((2, 18)), NVEC)
    assert dist.logits.shape == (2, 6, 3)
    np.testing.assert_allclose(dist.entropy(), [4 * math.log(3) + 2 * math.log(2)] * 2, rtol=1e-6, atol=1e-6)  # [nats]
    action = jnp.array([[0, 1, 2, 0, 1, 0], [2, 2, 2, 2, 1, 1]], jnp.int32)
    expected = [-(4 * math.log(3) + 2 * math.log(2))] * 2
    np.testing.assert_allclose(dist.log_prob(action), expected, rtol=1e-6, atol=1e-6)  # [nats]
    samples = jax.vmap(dist.sample)(jax.random.split(jax.random.key(0), 500))
    assert samples.shape == (500, 2, 6) and samples.dtype == jnp.int32
    assert np.all(np.asarray(samples) < np.asarray(NVEC))
    assert np.asarray(samples[..., 4:]).max() == 1 and np.asarray(samples[..., :4]).max() == 2

    def loss(flat):
        d = MultiCategorical.from_flat(flat, NVEC)
        return jnp.sum(d.entropy() + d.log_prob(action))

    grad = jax.grad(loss)(jax.random.normal(jax.random.key(1), (2, 18)))
    assert np.all(np.isfinite(grad))
    assert np.all(np.asarray(grad).reshape(2, 6, 3)[:, 4:, 2] == 0.0)


def test_diag_gaussian_by_hand():
    dist = DiagGaussian(jnp.array([0.0, 1.0]), jnp.log(jnp.array([1.0, 2.0])))
    half_log_2pi = 0.5 * math.log(2 * math.pi)
    expected = (-0.5 * 0.5**2 - half_log_2pi) + (-0.5 * 0.25**2 - math.log(2) - half_log_2pi)
    np.testing.assert_allclose(dist.log_prob(jnp.array([0.5, 1.5])), expected, rtol=1e-6, atol=1e-6)  # [nats]
    entropy = math.log(2 * math.pi * math.e) + math.log(2)
    np.testing.assert_allclose(dist.entropy(), entropy, rtol=1e-6, atol=1e-6)  # [nats]
    np.testing.assert_array_equal(dist.mode(), [0.0, 1.0])
    samples = jax.vmap(dist.sample)(jax.random.split(jax.random.key(0), 4000))
    # [action]: a sample std's error is relative (sigma / sqrt(2n) = 1.1% here) and neither std is near 0
    np.testing.assert_allclose(samples.std(0), [1.0, 2.0], rtol=0.05, atol=0.0)


def test_unused_bindings_are_masked_in_every_action_type():
    """With `used`, an unused binding's entry stays "off" and adds nothing to log-probability or entropy, so
    neither depends on its logits; used entries are as before."""
    used = jnp.array([True, False, False, False, False, True])
    head = jax.random.normal(jax.random.key(0), (18,))
    other = head.at[3:15].set(5.0)  # logits of the unused entries 1..4 only
    action = jnp.array([2, 0, 0, 0, 0, 1], jnp.int32)
    masked, plain = action_distribution("multi-discrete", head, used=used), action_distribution("multi-discrete", head)
    moved = action_distribution("multi-discrete", other, used=used)
    np.testing.assert_allclose(masked.log_prob(action), moved.log_prob(action), rtol=1e-6, atol=1e-6)  # [nats]
    np.testing.assert_allclose(masked.entropy(), moved.entropy(), rtol=1e-6, atol=1e-6)  # [nats]
    kept = MultiCategorical(plain.logits[jnp.array([0, 5])])
    np.testing.assert_allclose(masked.entropy(), kept.entropy(), rtol=1e-6, atol=1e-6)  # [nats]
    samples = jax.vmap(masked.sample)(jax.random.split(jax.random.key(1), 200))
    assert not np.asarray(samples[:, 1:5]).any() and np.asarray(samples[:, 0]).any()

    discrete = action_distribution("discrete", jnp.zeros(11), used=used)  # no-op, motor 0 both ways, thruster 1
    np.testing.assert_allclose(discrete.entropy(), math.log(4), rtol=1e-6, atol=1e-6)  # [nats]
    assert set(np.asarray(jax.vmap(discrete.sample)(jax.random.split(jax.random.key(2), 400))).tolist()) == {
        0,
        1,
        2,
        10,
    }

    gaussian = action_distribution("continuous", jnp.zeros(6), jnp.zeros(6), used=used)
    full = action_distribution("continuous", jnp.zeros(6), jnp.zeros(6))
    np.testing.assert_allclose(gaussian.entropy(), full.entropy() / 3, rtol=1e-6, atol=1e-6)  # [nats]
    half_log_2pi = 0.5 * math.log(2 * math.pi)  # each zero-mean, unit entry at 0 has log-density -half_log_2pi
    expected = full.log_prob(jnp.array([0.5, 0, 0, 0, 0, 0.0])) + 4 * half_log_2pi
    log_prob = gaussian.log_prob(jnp.array([0.5, 9, 9, 9, 9, 0.0]))
    np.testing.assert_allclose(log_prob, expected, rtol=1e-6, atol=1e-6)  # [nats]


def test_masking_needs_an_entity_model():
    with pytest.raises(ConfigError, match="model.mask_unused_actions: needs an entity model"):
        ModelSettings(name="flat-mlp", mask_unused_actions=True)


# --- models ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("action_type", ACTION_TYPES)
@pytest.mark.parametrize(("model", "observation"), MODEL_OBSERVATION_PAIRS)
def test_output_shapes(model, observation, action_type):
    """Value (B,) and actions in the encoding of `kinetix_cli.env.actions`, traced on real observations, for
    every model with every observation it reads (flat-mlp flattens the pixel image: one value per env)."""
    obs = observations("s", observation)
    net = tiny(model, action_type, observation)

    def run(obs):
        params = net.init(jax.random.key(0), obs)
        dist, value = net.apply(params, obs)
        action = dist.sample(jax.random.key(1))
        return value, action, dist.mode(), dist.log_prob(action), dist.entropy()

    value, action, mode, log_prob, entropy = jax.eval_shape(run, obs)
    shape, dtype = ACTION_ENCODING[action_type]
    assert value.shape == log_prob.shape == entropy.shape == (BATCH,)
    assert action.shape == mode.shape == (BATCH, *shape)
    assert action.dtype == mode.dtype == dtype


@pytest.mark.parametrize(("model", "observation"), REFUSED_PAIRS)
def test_a_model_that_cannot_read_the_observation_is_refused_in_one_line(model, observation):
    """Every model/observation pair works (`test_output_shapes`) or is refused: by the config, in one line naming
    both keys, and by `make_network`."""
    env = EnvSettings(observation=observation)
    with pytest.raises(ConfigError, match=f"model.name: '{model}' needs env.observation") as info:
        ExperimentConfig(env=env, model=ModelSettings(name=model), ppo=PPOSettings(total_timesteps=10**6))
    assert "\n" not in str(info.value)
    with pytest.raises(ValueError, match="cannot read"):
        make_network(ModelSettings(name=model), env)


def test_default_parameter_counts():
    """Default sizes (5 x 128 actor and critic, width 128); the reference transformer has ~786K."""
    counts = {}
    for model in MODEL_NAMES:
        obs = observations("s", MODEL_OBSERVATIONS[model][0])
        net = make_network(ModelSettings(name=model), EnvSettings(observation=MODEL_OBSERVATIONS[model][0]))
        counts[model] = parameter_count(jax.eval_shape(net.init, jax.random.key(0), obs))
    assert counts == {"flat-mlp": 170_643, "pi-mlp": 342_675, "rel-mlp": 656_019, "transformer": 738_195}


@functools.cache
def entity_model(model: str):
    """(jitted apply returning (logits, value), params) of a tiny entity model initialised on size s."""
    net = tiny(model)
    params = jax.jit(net.init)(jax.random.key(0), observations("s", "symbolic-entity"))

    @jax.jit
    def apply(params, obs):
        dist, value = net.apply(params, obs)
        return dist.logits, value

    return apply, params


ENTITY_MODELS = ("pi-mlp", "rel-mlp", "transformer")
SLOW_TRANSFORMER = ("pi-mlp", "rel-mlp", pytest.param("transformer", marks=pytest.mark.slow))
"""The two checks whose transformer compile costs ~10 s each run it in make test-all only."""


@pytest.mark.parametrize("model", SLOW_TRANSFORMER)
def test_initial_policy_is_near_uniform(model):
    apply, params = entity_model(model)
    logits, value = apply(params, observations("s", "symbolic-entity"))
    assert np.all(np.isfinite(value))
    np.testing.assert_allclose(MultiCategorical(logits).entropy(), 4 * math.log(3) + 2 * math.log(2), atol=0.01)


@pytest.mark.parametrize("model", SLOW_TRANSFORMER)
def test_a_masking_model_leaves_the_bindings_a_level_does_not_use_off(model):
    """On real observations, a model with `mask_unused_actions` samples "off" on every binding that
    `used_bindings` says moves nothing, and still samples the others."""
    obs = observations("s", "symbolic-entity")
    net = make_network(
        ModelSettings(name=model, width=16, actor_critic_layers=2, heads=4, mask_unused_actions=True),
        EnvSettings(size="s"),
    )

    @jax.jit
    def sample(keys):
        params = net.init(jax.random.key(0), obs)
        return jax.vmap(lambda k: net.apply(params, obs)[0].sample(k))(keys)

    actions = np.asarray(sample(jax.random.split(jax.random.key(1), 64)))
    used = np.asarray(used_bindings(obs))
    assert used.any() and not used.all()  # the random levels use some bindings and not others
    assert not actions[:, ~used].any() and actions[:, used].any()


@pytest.mark.parametrize("model", ENTITY_MODELS)
def test_masked_rows_do_not_change_the_output(model):
    obs = observations("s", "symbolic-entity")
    apply, params = entity_model(model)
    # Mask joint 0 (both directions) in every scene; its rows then hold whatever they like.
    joint_mask = obs.joint_mask.at[:, 0].set(False).at[:, 1].set(False)
    base = obs.replace(joint_mask=joint_mask)
    noise = lambda key, x: x + 10.0 * jax.random.normal(key, x.shape)  # noqa: E731
    k1, k2, k3 = jax.random.split(jax.random.key(3), 3)
    perturbed = base.replace(
        polygons=jnp.where(obs.polygon_mask[..., None], obs.polygons, noise(k1, obs.polygons)),
        joints=jnp.where(joint_mask[..., None], obs.joints, noise(k2, obs.joints)),
        joint_src=jnp.zeros_like(obs.joint_src),
        joint_dst=jnp.where(joint_mask, obs.joint_dst, 1),
    )
    assert not np.all(obs.polygon_mask)
    for want, got in zip(apply(params, base), apply(params, perturbed), strict=True):
        np.testing.assert_allclose(got, want, rtol=1e-5, atol=1e-6)
    # The unmasked rows do matter.
    moved = base.replace(polygons=jnp.where(obs.polygon_mask[..., None], noise(k3, obs.polygons), obs.polygons))
    assert not np.allclose(apply(params, moved)[1], apply(params, base)[1])


@pytest.mark.parametrize("model", ENTITY_MODELS)
def test_the_arena_sides_rows_are_never_read(model):
    """The walls' and ceiling's rows, masked in every observation, change no output bit (pi-mlp and rel-mlp leave
    them out of their encoders)."""
    obs = observations("s", "symbolic-entity")
    apply, params = entity_model(model)
    sides = np.zeros(obs.polygon_mask.shape[-1], bool)
    sides[ARENA_SIDES.start : ARENA_SIDES.stop] = True
    assert not obs.polygon_mask[:, sides].any()
    noisy = obs.replace(
        polygons=jnp.where(sides[:, None], 5.0 + jax.random.normal(jax.random.key(4), obs.polygons.shape), obs.polygons)
    )
    for want, got in zip(apply(params, obs), apply(params, noisy), strict=True):
        np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("model", ["pi-mlp", "rel-mlp"])
def test_the_polygon_encoder_computes_no_arena_side_row(model):
    _, params = entity_model(model)
    obs = observations("s", "symbolic-entity")
    rows = []

    def record(next_fun, args, kwargs, context):
        if isinstance(context.module, nn.Dense) and "polygon_encoder" in context.module.scope.path:
            rows.append(args[0].shape[-2])
        return next_fun(*args, **kwargs)

    with nn.intercept_methods(record):
        jax.eval_shape(tiny(model).apply, params, obs)
    polygons = obs.polygons.shape[-2]
    assert rows and set(rows) == {polygons - len(ARENA_SIDES)}


def permute_entities(obs, polygon_order, circle_order, joint_order, thruster_order):
    """The same scenes with the entity slots of a batched `EntityObservation` reordered (new slot i = old order[i])."""
    p = obs.polygons.shape[1]
    old_of_new = np.concatenate([polygon_order, p + np.asarray(circle_order)])
    new_of_old = jnp.asarray(np.argsort(old_of_new))
    return obs.replace(
        polygons=obs.polygons[:, polygon_order],
        circles=obs.circles[:, circle_order],
        polygon_mask=obs.polygon_mask[:, polygon_order],
        circle_mask=obs.circle_mask[:, circle_order],
        joints=obs.joints[:, joint_order],
        joint_mask=obs.joint_mask[:, joint_order],
        joint_src=new_of_old[obs.joint_src[:, joint_order]],
        joint_dst=new_of_old[obs.joint_dst[:, joint_order]],
        thrusters=obs.thrusters[:, thruster_order],
        thruster_mask=obs.thruster_mask[:, thruster_order],
        thruster_body=new_of_old[obs.thruster_body[:, thruster_order]],
        attention_mask=obs.attention_mask[:, :, old_of_new][:, :, :, old_of_new],
    )


@pytest.mark.parametrize("model", ENTITY_MODELS)
def test_slot_order_does_not_change_the_output(model):
    obs = observations("s", "symbolic-entity")
    apply, params = entity_model(model)
    # Every order of the slots that can hold a shape: the floor (0) and the free polygon slots (4, ...); the arena
    # sides (1..3) are masked in every observation and stay where they are (`env.observations.ARENA_SIDES`).
    shuffled = permute_entities(obs, [4, 1, 2, 3, 0], [1, 0], [1, 0], [0])
    assert not np.array_equal(shuffled.polygons, obs.polygons)
    for want, got in zip(apply(params, obs), apply(params, shuffled), strict=True):
        np.testing.assert_allclose(got, want, rtol=1e-4, atol=1e-5)


@pytest.mark.parametrize("model", ENTITY_MODELS)
def test_entity_model_params_work_across_sizes(model):
    """Params initialised on size s apply to size m observations, and their tree is the one m would build."""
    apply, params = entity_model(model)
    obs_m = observations("m", "symbolic-entity")
    expected = jax.eval_shape(tiny(model).init, jax.random.key(0), obs_m)
    assert jax.tree.structure(params) == jax.tree.structure(expected)
    assert [a.shape for a in jax.tree.leaves(params)] == [b.shape for b in jax.tree.leaves(expected)]
    logits, value = apply(params, obs_m)
    assert logits.shape == (BATCH, 6, 3) and value.shape == (BATCH,)
    assert np.all(np.isfinite(value))


def test_batched_apply_matches_one_observation():
    apply, params = entity_model("transformer")
    obs = observations("s", "symbolic-entity")
    one = jax.tree.map(lambda x: x[1], obs)
    dist, value = jax.jit(tiny("transformer").apply)(params, one)
    batched_logits, batched_value = apply(params, obs)
    np.testing.assert_allclose(value, batched_value[1], rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(dist.logits, batched_logits[1], rtol=1e-5, atol=1e-6)


def test_gradients_are_finite_through_masks():
    """-inf padding logits and fully masked attention rows leave every gradient finite."""
    obs = observations("s", "symbolic-entity")
    net = tiny("transformer")
    _, params = entity_model("transformer")

    def loss(params):
        dist, value = net.apply(params, obs)
        action = dist.sample(jax.random.key(2))
        return jnp.sum(dist.log_prob(action) + 0.01 * dist.entropy() + value**2)

    grads = jax.jit(jax.grad(loss))(params)
    assert all(np.all(np.isfinite(g)) for g in jax.tree.leaves(grads))


# make test: rel-mlp (the shipped agents' model); the transformer, through the same wrapper, in make test-all (~9 s)
@pytest.mark.parametrize("model", ["rel-mlp", pytest.param("transformer", marks=pytest.mark.slow)])
def test_a_bfloat16_network_keeps_float32_parameters_and_outputs_and_computes_near_float32(model):
    """`model.compute: bfloat16`: the same float32 parameters (a plain agent loads), float32 outputs and gradients,
    and outputs within bfloat16's rounding of the float32 network's (8 bits of mantissa: ~0.4% per operation)."""
    settings = ModelSettings(name=model, width=16, actor_critic_layers=2, heads=4)
    env = EnvSettings(size="s", observation="symbolic-entity")
    plain, mixed = make_network(settings, env), make_network(dataclasses.replace(settings, compute="bfloat16"), env)
    obs = observations("s", "symbolic-entity")
    params = jax.jit(plain.init)(jax.random.key(0), obs)
    assert jax.tree.structure(jax.jit(mixed.init)(jax.random.key(0), obs)) == jax.tree.structure(params)

    def loss(net, params):
        dist, value = net.apply(params, obs)
        return jnp.sum(dist.log_prob(jnp.ones((BATCH, 6), jnp.int32)) + value**2), (dist.logits, value)

    (_, (logits, value)), grads = jax.jit(jax.value_and_grad(functools.partial(loss, mixed), has_aux=True))(params)
    _, (plain_logits, plain_value) = jax.jit(functools.partial(loss, plain))(params)
    assert logits.dtype == value.dtype == jnp.float32
    assert all(g.dtype == jnp.float32 and np.all(np.isfinite(g)) for g in jax.tree.leaves(grads))
    assert np.any(np.asarray(logits) != np.asarray(plain_logits)), "computed in bfloat16, not float32"
    np.testing.assert_allclose(logits, plain_logits, rtol=0.05, atol=0.02)  # [logit]
    np.testing.assert_allclose(value, plain_value, rtol=0.05, atol=0.02)  # [return]


def test_kl_divergence_by_hand_and_by_integration():
    """Categorical against the sum by hand, multi-discrete per entry with unused and padding choices adding nothing
    (gradients finite), a Gaussian against a numerical integral; 0 between a distribution and itself."""
    p, q = np.array([0.5, 0.25, 0.25]), np.array([0.2, 0.2, 0.6])
    by_hand = float(np.sum(p * np.log(p / q)))
    kl = kl_divergence(Categorical(jnp.log(jnp.asarray(p))), Categorical(jnp.log(jnp.asarray(q))))
    np.testing.assert_allclose(float(kl), by_hand, atol=1e-6)  # [nats]
    used = jnp.array([True, False, True, False, True, False])
    a = MultiCategorical.from_flat(jax.random.normal(jax.random.key(0), (18,)), NVEC, used)
    b_flat = jax.random.normal(jax.random.key(1), (18,))
    b = MultiCategorical.from_flat(b_flat, NVEC, used)
    entry = lambda d, i: Categorical(d.logits[i, : NVEC[i]])  # noqa: E731
    per_entry = [float(kl_divergence(entry(a, i), entry(b, i))) for i in (0, 2, 4)]  # the used entries
    np.testing.assert_allclose(float(kl_divergence(a, b)), sum(per_entry), atol=1e-6)  # [nats]
    np.testing.assert_allclose(float(kl_divergence(a, a)), 0.0, atol=1e-6)  # [nats]
    grad = jax.grad(lambda f: kl_divergence(a, MultiCategorical.from_flat(f, NVEC, used)))(b_flat)
    assert np.isfinite(np.asarray(grad)).all()
    g1, g2 = DiagGaussian(jnp.array([0.3]), jnp.array([-0.5])), DiagGaussian(jnp.array([-0.4]), jnp.array([0.2]))
    x = np.linspace(-12.0, 12.0, 200_001)
    log_1, log_2 = (np.asarray(jax.vmap(g.log_prob)(jnp.asarray(x[:, None], jnp.float32))) for g in (g1, g2))
    integral = float(np.sum(np.exp(log_1) * (log_1 - log_2)) * (x[1] - x[0]))
    np.testing.assert_allclose(float(kl_divergence(g1, g2)), integral, atol=1e-4)  # [nats]: the grid's error


# --- the mirror image ----------------------------------------------------------------------------------------
def _probabilities(dist, kind: str) -> np.ndarray:
    """Every action's probability (multi-discrete: per entry), to compare two distributions."""
    if kind == "continuous":
        return np.concatenate([np.asarray(dist.mean), np.broadcast_to(dist.log_std, dist.mean.shape)], -1)
    return np.asarray(jax.nn.softmax(dist.logits, axis=-1))


@pytest.mark.parametrize("kind", ACTION_TYPES)
def test_a_mirrored_distribution_gives_each_mirrored_action_its_probability(kind):
    head = jax.random.normal(jax.random.key(1), (5, {"multi-discrete": 18, "discrete": 11, "continuous": 6}[kind]))
    dist = action_distribution(kind, head, jnp.full(6, -0.5) if kind == "continuous" else None)
    actions = jax.vmap(lambda k: sample_action(kind, k))(jax.random.split(jax.random.key(2), 5))
    # [nats]: the same float32 terms summed in another order
    np.testing.assert_allclose(mirrored(dist).log_prob(mirror_action(kind, actions)), dist.log_prob(actions), atol=1e-5)
    np.testing.assert_array_equal(_probabilities(mirrored(mirrored(dist)), kind), _probabilities(dist, kind))
    for geometric in (False, True):
        mix = averaged(dist, mirrored(dist), geometric)
        if kind != "continuous":  # every choice (or entry's choice) has probability in [0, 1], summing to 1
            np.testing.assert_allclose(_probabilities(mix, kind).sum(-1), 1.0, atol=1e-6)  # [1]
        # the mix of a distribution and its mirror image is its own mirror image: left-right symmetric
        np.testing.assert_allclose(_probabilities(mirrored(mix), kind), _probabilities(mix, kind), atol=1e-6)  # [1]


def mirrored_probabilities(dist):
    """The multi-discrete distribution's probabilities (`_probabilities`) and its mirror image's; traceable."""
    return tuple(jax.nn.softmax(d.logits, axis=-1) for d in (dist, mirrored(dist)))


JOIN_MODES = [pytest.param(m, marks=[] if m == "geometric" else pytest.mark.slow) for m in MIRROR_MODES]
"""make test holds one mode to it (each costs a compile of the model, ~10 s); the modes share `_joined` and
`mirrored`, and the mean and geometric joins' own symmetry is checked above; make test-all runs all three."""


@pytest.mark.parametrize("mode", JOIN_MODES)
def test_a_policy_joined_with_its_mirror_image_is_left_right_equivariant(mode):
    """The joined policy in a state and in the state's mirror image choose mirror-image actions with equal
    probabilities, although the network alone does not."""
    network = tiny("rel-mlp")
    env = MirrorPairEnv.of(KinetixEnv(SIZES["s"], observation="symbolic-entity"))
    state = env.initial_state(index_level(random_levels(SIZES["s"], 4, 0), 1))
    pair, twin_pair = env.observe(state), env.observe(jax.jit(mirror_env_state)(state))
    params = jax.jit(network.init)(jax.random.key(0), pair[0])
    params = jax.jit(lambda p: jax.tree.map(lambda x: x * 8.0, p))(params)  # far from uniform: a difference shows
    joined = jax.jit(lambda params, pair: mirrored_probabilities(mirror_joined(network, params, pair, mode)))
    (here, _), (_, there) = joined(params, pair), joined(params, twin_pair)
    # [1]: the mirrored twice state differs from the state by the rounding of 5 - x (~1e-7 m)
    np.testing.assert_allclose(there, here, atol=1e-4)
    alone = jax.jit(lambda params, obs: mirrored_probabilities(network.apply(params, obs)[0]))
    (plain, _), (_, plain_there) = alone(params, pair[0]), alone(params, twin_pair[0])
    gap = np.abs(plain_there - plain).max()
    assert gap > 0.05, gap


@pytest.mark.parametrize("mode", JOIN_MODES[:2])  # make test: geometric, as the equivariance test above
def test_a_mirror_joined_model_has_the_plain_models_parameters_and_acts_joined(mode):
    """`model.mirror`: the same parameter tree as the plain model (plain agents load into it), the joined
    distribution of `mirror_joined`, the mean of the two views' values; a bad mode is a config error."""
    plain = tiny("rel-mlp")
    joined = make_network(ModelSettings(name="rel-mlp", width=16, actor_critic_layers=2, mirror=mode), plain_env())
    env = MirrorPairEnv.of(KinetixEnv(SIZES["s"], observation="symbolic-entity"))
    pair = env.observe(env.initial_state(index_level(random_levels(SIZES["s"], 4, 0), 2)))
    params = jax.jit(plain.init)(jax.random.key(0), pair[0])
    assert jax.tree.structure(jax.eval_shape(joined.init, jax.random.key(0), pair)) == jax.tree.structure(params)
    dist, value = jax.jit(joined.apply)(params, pair)
    expected = jax.jit(lambda p, o: mirror_joined(plain, p, o, mode))(params, pair)
    np.testing.assert_allclose(np.asarray(dist.logits), np.asarray(expected.logits), atol=1e-6)  # [nats]
    values = [float(jax.jit(plain.apply)(params, obs)[1]) for obs in pair]
    np.testing.assert_allclose(float(value), np.mean(values), atol=1e-6)  # [1]
    with pytest.raises(ConfigError, match="model.mirror: expected one of 'none', 'mean', 'geometric'"):
        ModelSettings(name="rel-mlp", mirror="value")


def plain_env() -> EnvSettings:
    return EnvSettings(size="s", observation="symbolic-entity")
