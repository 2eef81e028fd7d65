"""Actor-critic networks: flat MLP, permutation-invariant MLP and the entity transformer.

Every model is a `flax.linen` Module whose ``__call__(obs)`` returns ``(distribution, value)``:

- ``obs``: the ``symbolic-flat`` vector (..., F) or the ``pixels`` image (..., 125, 125, 3) for `FlatMLP`; an
  `EntityObservation` for `PermutationInvariantMLP` and `EntityTransformer` (`constants.MODEL_OBSERVATIONS`).
- ``distribution``: a `kinetix_cli.rl.distributions` pytree over the action type's actions (see
  `action_distribution`).
- ``value``: (...,) float32 critic estimate.

Batching: the models are written for inputs with any leading batch shape ``...`` (none for one observation,
(num_envs,) for a rollout step, (steps, num_envs) for a whole rollout), and every output carries the same
leading shape, so callers apply them to batches directly; `jax.vmap` over ``apply`` works as well.

The entity models see no slot index and no positional encoding: their parameters do not depend on the level
size (the same params apply to s, m and l observations) and their output does not depend on the order of the
entity slots that can hold a shape. Masked entity rows never reach the output; the arena's walls and ceiling, masked
in every observation (`env.observations.ARENA_SIDES`), are not even computed by pi-mlp's and rel-mlp's encoders.

Initialisation follows PureJaxRL: orthogonal kernels with gain sqrt(2) in hidden layers, 0.01 on the actor
head and 1.0 on the critic head, zero biases; the attention and gate layers keep flax's defaults.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import flax.linen as nn
import jax
import jax.numpy as jnp
from flax import traverse_util

from engine import Scene
from kinetix_cli.config import EnvSettings, ExperimentConfig, ModelSettings
from kinetix_cli.constants import MODEL_OBSERVATIONS, NUM_ATTENTION_CHANNELS, ROLE_NAMES
from kinetix_cli.env.actions import action_space, discrete_choice_bindings
from kinetix_cli.env.episode import Policy
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import empty_bindings, make_level
from kinetix_cli.env.observations import (
    ARENA_SIDES,
    JOINT_BINDING,
    SHAPE_COS,
    SHAPE_FEATURES,
    SHAPE_POSITION,
    SHAPE_ROLE,
    SHAPE_SIN,
    THRUSTER_ANCHOR,
    THRUSTER_BINDING,
    THRUSTER_DIRECTION,
    EntityObservation,
    used_bindings,
)
from kinetix_cli.rl.distributions import (
    Categorical,
    DiagGaussian,
    Distribution,
    MultiCategorical,
    averaged,
    chosen,
    mirrored,
)
from kinetix_cli.rl.trees import tree_mismatch

FEATURE_AXES = {"symbolic-flat": 1, "pixels": 3}
"""Trailing axes of one observation that `FlatMLP` flattens into its input vector."""

ACTIVATIONS: dict[str, Callable[[jax.Array], jax.Array]] = {"tanh": nn.tanh, "relu": nn.relu}


def orthogonal(gain: float) -> nn.initializers.Initializer:
    """Orthogonal kernel initialiser with `gain` (PureJaxRL)."""
    return nn.initializers.orthogonal(gain)


def activation_fn(name: str) -> Callable[[jax.Array], jax.Array]:
    """The activation called `name`; raises ValueError naming the choices."""
    if name not in ACTIVATIONS:
        raise ValueError(f"unknown activation {name!r}; choose one of {', '.join(ACTIVATIONS)}")
    return ACTIVATIONS[name]


def masked_mean(x: jax.Array, mask: jax.Array) -> jax.Array:
    """(..., D) mean of rows x (..., R, D) where mask (..., R) is True; 0 when no row is."""
    total = jnp.sum(jnp.where(mask[..., None], x, 0.0), axis=-2)
    count = jnp.sum(mask, axis=-1, keepdims=True).astype(x.dtype)
    return total / jnp.maximum(count, 1.0)


class MLP(nn.Module):
    """`depth` dense layers of `width` units, each followed by the activation (gain sqrt(2) orthogonal init).

    Attributes:
        width: units per layer.
        depth: number of layers (0: identity).
        activation: a name in `ACTIVATIONS`.
    """

    width: int
    depth: int
    activation: str = "tanh"

    @nn.compact
    def __call__(self, x: jax.Array) -> jax.Array:
        """(..., D) -> (..., width)."""
        act = activation_fn(self.activation)
        for _ in range(self.depth):
            x = act(nn.Dense(self.width, kernel_init=orthogonal(math.sqrt(2.0)), bias_init=nn.initializers.zeros)(x))
        return x


def action_distribution(
    action_type: str, head: jax.Array, log_std: jax.Array | None = None, used: jax.Array | None = None
) -> Distribution:
    """The distribution of `action_type` from the actor head's output.

    head: (..., H) with H = 6 * 3 (multi-discrete: per-entry logits padded to 3 choices), 11 (discrete) or 6
        (continuous: the mean). log_std: (6,) continuous log standard deviation (state-independent).
    used: (..., 6) bool bindings that move something (`env.observations.used_bindings`), or None (all). The
        others are masked: a multi-discrete entry stays "off", a discrete choice that drives one is impossible, a
        continuous entry adds nothing to log-density and entropy. Sampled actions then drive the same scene,
        while the policy's log-probability and entropy only count the choices that matter.
    """
    space = action_space(action_type)
    if action_type == "multi-discrete":
        return MultiCategorical.from_flat(head, space.nvec, used)
    if action_type == "discrete":
        if used is not None:
            bindings = jnp.asarray(discrete_choice_bindings())
            valid = (bindings < 0) | jnp.take(used, jnp.maximum(bindings, 0), axis=-1)
            head = jnp.where(valid, head, -jnp.inf)
        return Categorical(head)
    return DiagGaussian(head, jnp.broadcast_to(log_std, head.shape), used)


def head_size(action_type: str) -> int:
    """Outputs of the actor head for `action_type` (see `action_distribution`)."""
    space = action_space(action_type)
    if action_type == "multi-discrete":
        return len(space.nvec) * max(space.nvec)
    if action_type == "discrete":
        return space.nvec[0]
    return space.shape[0]


class ActorCriticHeads(nn.Module):
    """Separate actor and critic MLPs on a shared embedding (the reference's 5 x 128 tanh by default).

    Attributes:
        action_type: one of `constants.ACTION_TYPES`.
        hidden_width, hidden_depth: width and number of hidden layers of each MLP.
        activation: a name in `ACTIVATIONS`.
    """

    action_type: str
    hidden_width: int = 128
    hidden_depth: int = 5
    activation: str = "tanh"

    @nn.compact
    def __call__(self, x: jax.Array, used: jax.Array | None = None) -> tuple[Distribution, jax.Array]:
        """(..., D) embedding -> (distribution, (...,) value); `used` masks bindings (`action_distribution`)."""
        actor = MLP(self.hidden_width, self.hidden_depth, self.activation, name="actor")(x)
        head = nn.Dense(head_size(self.action_type), kernel_init=orthogonal(0.01), name="actor_head")(actor)
        log_std = None
        if self.action_type == "continuous":
            log_std = self.param("log_std", nn.initializers.zeros, (head.shape[-1],))
        critic = MLP(self.hidden_width, self.hidden_depth, self.activation, name="critic")(x)
        value = nn.Dense(1, kernel_init=orthogonal(1.0), name="critic_head")(critic)[..., 0]
        return action_distribution(self.action_type, head, log_std, used), value


class FlatMLP(nn.Module):
    """Actor and critic MLPs on one observation flattened into a vector: the ``symbolic-flat`` vector
    (size-specific: params fit one size) or the ``pixels`` image (a baseline; 46,875 inputs).

    Attributes:
        action_type: one of `constants.ACTION_TYPES`.
        observation: 'symbolic-flat' or 'pixels' (`FEATURE_AXES` says how many trailing axes are one observation).
        hidden_width, hidden_depth, activation: see `ActorCriticHeads`.
    """

    action_type: str = "multi-discrete"
    observation: str = "symbolic-flat"
    hidden_width: int = 128
    hidden_depth: int = 5
    activation: str = "tanh"

    @nn.compact
    def __call__(self, obs: jax.Array) -> tuple[Distribution, jax.Array]:
        """obs: (..., F) vectors or (..., H, W, 3) images, float32 -> (distribution, (...,) value)."""
        axes = FEATURE_AXES[self.observation]
        x = obs.reshape(*obs.shape[: obs.ndim - axes], -1)
        return ActorCriticHeads(self.action_type, self.hidden_width, self.hidden_depth, self.activation)(x)


def encode_polygons(mlp: Callable[[jax.Array], jax.Array], rows: jax.Array, mask: jax.Array) -> jax.Array:
    """(..., P, d) `mlp` of each polygon row of (..., P, F) `rows`, 0 where `mask` is False. The arena sides' rows
    (`ARENA_SIDES`), masked in every observation, are left out of the computation and their zeros put back in
    place: the same output, and 8.8% fewer FLOPs in the general recipe's update (rel-mlp 64 at size s)."""
    start, stop = ARENA_SIDES.start, ARENA_SIDES.stop
    h = mlp(jnp.concatenate([rows[..., :start, :], rows[..., stop:, :]], axis=-2))
    sides = jnp.zeros((*h.shape[:-2], stop - start, h.shape[-1]), h.dtype)
    h = jnp.concatenate([h[..., :start, :], sides, h[..., start:, :]], axis=-2)
    return jnp.where(mask[..., None], h, 0.0)


class EntityEncoders(nn.Module):
    """Per-type MLPs mapping polygon, circle, joint and thruster rows to `width`.

    Attributes:
        width: embedding width d.
        depth: dense layers per encoder (>= 1), each followed by the activation.
        activation: a name in `ACTIVATIONS`.
    """

    width: int
    depth: int = 1
    activation: str = "tanh"

    @nn.compact
    def __call__(self, obs: EntityObservation) -> tuple[jax.Array, jax.Array, jax.Array, jax.Array]:
        """(polygons (..., P, d), circles (..., C, d), joints (..., 2J, d), thrusters (..., T, d)), masked rows 0."""

        def encode(rows, mask, name):
            h = MLP(self.width, self.depth, self.activation, name=name)(rows)
            return jnp.where(mask[..., None], h, 0.0)

        polygon_encoder = MLP(self.width, self.depth, self.activation, name="polygon_encoder")
        return (
            encode_polygons(polygon_encoder, obs.polygons, obs.polygon_mask),
            encode(obs.circles, obs.circle_mask, "circle_encoder"),
            encode(obs.joints, obs.joint_mask, "joint_encoder"),
            encode(obs.thrusters, obs.thruster_mask, "thruster_encoder"),
        )


def shape_mask(obs: EntityObservation) -> jax.Array:
    """(..., N) bool: unmasked shapes, polygons then circles (the entity index order)."""
    return jnp.concatenate([obs.polygon_mask, obs.circle_mask], axis=-1)


class PermutationInvariantMLP(nn.Module):
    """Deep-sets baseline: per-type entity encoders, a masked mean per type, then actor and critic MLPs.

    The readout concatenates the four per-type means (polygon, circle, joint, thruster) and the gravity:
    4 * width + 2 values. Joint and thruster rows are pooled without their body indices.

    Attributes:
        action_type: one of `constants.ACTION_TYPES`.
        width: entity embedding width d.
        encoder_depth: layers per entity encoder.
        hidden_width, hidden_depth, activation: see `ActorCriticHeads` (the activation is shared).
        mask_actions: fix the action entries of bindings that move nothing at "off" (`action_distribution`).
    """

    action_type: str = "multi-discrete"
    width: int = 128
    encoder_depth: int = 2
    hidden_width: int = 128
    hidden_depth: int = 5
    activation: str = "tanh"
    mask_actions: bool = False

    @nn.compact
    def __call__(self, obs: EntityObservation) -> tuple[Distribution, jax.Array]:
        """obs: `EntityObservation` with leading batch shape ... -> (distribution, (...,) value)."""
        polygons, circles, joints, thrusters = EntityEncoders(self.width, self.encoder_depth, self.activation)(obs)
        pooled = [
            masked_mean(polygons, obs.polygon_mask),
            masked_mean(circles, obs.circle_mask),
            masked_mean(joints, obs.joint_mask),
            masked_mean(thrusters, obs.thruster_mask),
            obs.gravity,
        ]
        x = jnp.concatenate(pooled, axis=-1)
        heads = ActorCriticHeads(self.action_type, self.hidden_width, self.hidden_depth, self.activation)
        return heads(x, used_bindings(obs) if self.mask_actions else None)


def gather_rows(rows: jax.Array, index: jax.Array) -> jax.Array:
    """(..., R, D) rows[..., index[r], :] of (..., N, D) rows for (..., R) int indices (any leading shape)."""
    return jnp.take_along_axis(rows, index[..., None], axis=-2)


def rotate(vectors: jax.Array, sin: jax.Array, cos: jax.Array) -> jax.Array:
    """(..., 2) vectors rotated by the angles whose (...,) sine and cosine are given."""
    x, y = vectors[..., 0], vectors[..., 1]
    return jnp.stack([cos * x - sin * y, sin * x + cos * y], axis=-1)


class RelationalMLP(nn.Module):
    """A permutation-invariant MLP that reads relations: what each actuator moves, which way a thruster pushes
    in the world, where each shape is relative to green and blue, and which action entry drives what.

    1. Each shape row gains its position relative to the green and to the blue shapes' centroids (4 values),
       then per-type encoders map shapes to width d.
    2. Each thruster row is joined with its world-frame direction and anchor offset (its body-frame values
       rotated by the body's angle) and its body's embedding; each joint row (both directions) with the
       embeddings of its src and dst bodies; an MLP per type maps them to d.
    3. Pooling keeps roles apart: a masked mean of the shapes of each role (neutral, green, blue, red), and one of
       the actuators on each action entry (motor bindings 0-3 by the joint rows' binding, thruster bindings 0-1),
       in action order, beside the means of all joints and all thrusters.
    4. These 12 d values, the gravity and the blue-minus-green centroid offset go to `ActorCriticHeads`.

    No slot index is read: the parameters fit every size and the output does not depend on the order of the slots
    that can hold a shape.

    Attributes:
        action_type: one of `constants.ACTION_TYPES`.
        width: embedding width d.
        encoder_depth: layers per shape and actuator encoder.
        mask_actions: fix the action entries of bindings that move nothing at "off" (`action_distribution`).
        hidden_width, hidden_depth, activation: see `ActorCriticHeads` (the activation is shared).
    """

    action_type: str = "multi-discrete"
    width: int = 128
    encoder_depth: int = 2
    hidden_width: int = 128
    hidden_depth: int = 5
    activation: str = "tanh"
    mask_actions: bool = False

    @nn.compact
    def __call__(self, obs: EntityObservation) -> tuple[Distribution, jax.Array]:
        """obs: `EntityObservation` with leading batch shape ... -> (distribution, (...,) value)."""
        p = obs.polygons.shape[-2]
        mask = shape_mask(obs)
        rows = jnp.concatenate([obs.polygons[..., :SHAPE_FEATURES], obs.circles[..., :SHAPE_FEATURES]], axis=-2)
        position, role = rows[..., SHAPE_POSITION], rows[..., SHAPE_ROLE] > 0.5
        centroid = lambda r: masked_mean(position, mask & role[..., r])  # noqa: E731
        green, blue = centroid(ROLE_NAMES.index("green")), centroid(ROLE_NAMES.index("blue"))
        relative = jnp.concatenate([position - green[..., None, :], position - blue[..., None, :]], axis=-1)
        relative = jnp.where(mask[..., None], relative, 0.0)

        def encode(x, row_mask, name):
            return jnp.where(row_mask[..., None], MLP(self.width, self.encoder_depth, self.activation, name=name)(x), 0)

        shapes = jnp.concatenate(
            [
                encode_polygons(
                    MLP(self.width, self.encoder_depth, self.activation, name="polygon_encoder"),
                    jnp.concatenate([obs.polygons, relative[..., :p, :]], -1),
                    obs.polygon_mask,
                ),
                encode(jnp.concatenate([obs.circles, relative[..., p:, :]], -1), obs.circle_mask, "circle_encoder"),
            ],
            axis=-2,
        )
        body = gather_rows(rows, obs.thruster_body)
        sin, cos = body[..., SHAPE_SIN], body[..., SHAPE_COS]
        world = [
            rotate(obs.thrusters[..., THRUSTER_DIRECTION], sin, cos),
            rotate(obs.thrusters[..., THRUSTER_ANCHOR], sin, cos),
        ]
        thrusters = encode(
            jnp.concatenate([obs.thrusters, *world, gather_rows(shapes, obs.thruster_body)], -1),
            obs.thruster_mask,
            "thruster_encoder",
        )
        ends = [gather_rows(shapes, obs.joint_src), gather_rows(shapes, obs.joint_dst)]
        joints = encode(jnp.concatenate([obs.joints, *ends], -1), obs.joint_mask, "joint_encoder")

        roles = [masked_mean(shapes, mask & role[..., r]) for r in range(len(ROLE_NAMES))]
        motor = obs.joints[..., JOINT_BINDING] > 0.5
        thrust = obs.thrusters[..., THRUSTER_BINDING] > 0.5
        bindings = [masked_mean(joints, obs.joint_mask & motor[..., k]) for k in range(motor.shape[-1])]
        bindings += [masked_mean(thrusters, obs.thruster_mask & thrust[..., k]) for k in range(thrust.shape[-1])]
        pooled = [masked_mean(joints, obs.joint_mask), masked_mean(thrusters, obs.thruster_mask)]
        x = jnp.concatenate([*roles, *bindings, *pooled, obs.gravity, blue - green], axis=-1)
        heads = ActorCriticHeads(self.action_type, self.hidden_width, self.hidden_depth, self.activation)
        return heads(x, used_bindings(obs) if self.mask_actions else None)


class Gate(nn.Module):
    """GRU-style gated residual (GTrXL, Parisotto et al. 2019): mixes the stream x with the update y.

    g = (1 - z) * x + z * tanh(W_g y + U_g (r * x)), r = sigmoid(W_r y + U_r x), z = sigmoid(W_z y + U_z x - bias).
    A positive `bias` starts the layer close to the identity.
    """

    bias: float = 2.0

    @nn.compact
    def __call__(self, x: jax.Array, y: jax.Array) -> jax.Array:
        """x, y: (..., d) -> (..., d)."""
        d = x.shape[-1]
        dense = lambda name: nn.Dense(d, use_bias=False, name=name)  # noqa: E731
        r = nn.sigmoid(dense("w_r")(y) + dense("u_r")(x))
        bias = self.param("bias", nn.initializers.constant(self.bias), (d,))
        z = nn.sigmoid(dense("w_z")(y) + dense("u_z")(x) - bias)
        h = jnp.tanh(dense("w_g")(y) + dense("u_g")(r * x))
        return (1.0 - z) * x + z * h


class TransformerLayer(nn.Module):
    """Pre-norm masked self-attention over shapes then a dense update, each joined by a `Gate`.

    Attributes:
        num_heads: attention heads; head size = d / num_heads.
        gate_bias: see `Gate`.
    """

    num_heads: int = 8
    gate_bias: float = 2.0

    @nn.compact
    def __call__(self, h: jax.Array, mask: jax.Array) -> jax.Array:
        """h: (..., N, d) shape embeddings; mask: (..., num_heads, N, N) bool (query, key) -> (..., N, d)."""
        d = h.shape[-1]
        attention = nn.MultiHeadDotProductAttention(num_heads=self.num_heads, qkv_features=d, out_features=d)
        y = attention(nn.LayerNorm(name="attention_norm")(h), mask=mask)
        h = Gate(self.gate_bias, name="attention_gate")(h, nn.relu(y))
        dense = nn.Dense(d, kernel_init=orthogonal(math.sqrt(2.0)), name="dense")
        e = nn.relu(dense(nn.LayerNorm(name="dense_norm")(h)))
        return Gate(self.gate_bias, name="dense_gate")(h, e)


class EntityTransformer(nn.Module):
    """The reference's default model: entity encoders, messages along joints and thrusters, gated attention.

    1. Per-type encoders map shape, joint and thruster rows to width d.
    2. Messages: each joint row's embedding is added to the embedding of its ``joint_dst`` shape (every joint
       appears in both directions, so both shapes receive one) and each thruster's to its ``thruster_body``.
    3. `num_layers` `TransformerLayer`s over the shapes; mask channel c of the observation's (4, N, N)
       ``attention_mask`` drives heads [c * k, (c + 1) * k) with k = num_heads / 4.
    4. Masked mean over shapes, concatenated with the gravity, into `ActorCriticHeads`.

    Attributes:
        action_type: one of `constants.ACTION_TYPES`.
        width: embedding width d (128: 8 heads of size 16).
        num_layers: transformer layers.
        num_heads: attention heads, a multiple of 4.
        encoder_depth: layers per entity encoder.
        mask_actions: fix the action entries of bindings that move nothing at "off" (`action_distribution`).
        gate_bias: see `Gate`.
        hidden_width, hidden_depth, activation: see `ActorCriticHeads` (the activation also ends the encoders).
    """

    action_type: str = "multi-discrete"
    width: int = 128
    num_layers: int = 2
    num_heads: int = 8
    encoder_depth: int = 1
    gate_bias: float = 2.0
    hidden_width: int = 128
    hidden_depth: int = 5
    activation: str = "tanh"
    mask_actions: bool = False

    @nn.compact
    def __call__(self, obs: EntityObservation) -> tuple[Distribution, jax.Array]:
        """obs: `EntityObservation` with leading batch shape ... -> (distribution, (...,) value)."""
        if self.num_heads % NUM_ATTENTION_CHANNELS or self.width % self.num_heads:
            raise ValueError(
                f"num_heads must be a multiple of {NUM_ATTENTION_CHANNELS} that divides width, "
                f"got num_heads={self.num_heads}, width={self.width}"
            )
        polygons, circles, joints, thrusters = EntityEncoders(self.width, self.encoder_depth, self.activation)(obs)
        h = jnp.concatenate([polygons, circles], axis=-2)
        mask = shape_mask(obs)
        n = h.shape[-2]
        # Messages: scatter-add as one-hot products, which batch over any leading shape.
        h = h + jnp.einsum("...rn,...rd->...nd", jax.nn.one_hot(obs.joint_dst, n, dtype=h.dtype), joints)
        h = h + jnp.einsum("...rn,...rd->...nd", jax.nn.one_hot(obs.thruster_body, n, dtype=h.dtype), thrusters)
        h = jnp.where(mask[..., None], h, 0.0)
        heads = jnp.repeat(obs.attention_mask, self.num_heads // NUM_ATTENTION_CHANNELS, axis=-3)
        for i in range(self.num_layers):
            h = TransformerLayer(self.num_heads, self.gate_bias, name=f"layer_{i}")(h, heads)
            h = jnp.where(mask[..., None], h, 0.0)
        x = jnp.concatenate([masked_mean(h, mask), obs.gravity], axis=-1)
        heads = ActorCriticHeads(self.action_type, self.hidden_width, self.hidden_depth, self.activation)
        return heads(x, used_bindings(obs) if self.mask_actions else None)


def make_network(model: ModelSettings, env: EnvSettings) -> nn.Module:
    """The actor-critic of an experiment: `model` is its `model` section, `env` its `env` section (the action type
    sets the heads, the observation the input). Raises ValueError for a model that cannot read the observation
    (`constants.MODEL_OBSERVATIONS`; a validated `ExperimentConfig` never has one). With `model.mirror` it is the
    `MirrorJoinedNetwork` of the plain model."""
    base = _plain_network(model, env)
    if model.compute != "float32":
        base = MixedPrecisionNetwork(base, jnp.dtype(model.compute))
    return base if model.mirror == "none" else MirrorJoinedNetwork(base, model.mirror)


def _plain_network(model: ModelSettings, env: EnvSettings) -> nn.Module:
    if env.observation not in MODEL_OBSERVATIONS[model.name]:
        raise ValueError(f"model {model.name!r} cannot read {env.observation!r} observations")
    heads = {"action_type": env.action, "hidden_width": model.width, "hidden_depth": model.actor_critic_layers}
    if model.name == "flat-mlp":
        return FlatMLP(observation=env.observation, **heads)
    heads["mask_actions"] = model.mask_unused_actions
    if model.name == "pi-mlp":
        return PermutationInvariantMLP(width=model.width, **heads)
    if model.name == "rel-mlp":
        return RelationalMLP(width=model.width, **heads)
    return EntityTransformer(width=model.width, num_layers=model.transformer_layers, num_heads=model.heads, **heads)


def params_mismatch(config: ExperimentConfig, params) -> str | None:
    """Why `params` do not fit the network of `config` (the first leaf missing, extra or of another shape or
    dtype than the network initialises), or None when they fit."""
    env, _ = make_env(config.env, pairs=config.model.reads_pairs)
    static = env.static
    level = make_level(Scene().build_numpy(static), empty_bindings(static.num_joints, static.num_thrusters))
    obs = jax.eval_shape(lambda: env.reset_to_level(level)[0])
    return tree_mismatch(jax.eval_shape(make_network(config.model, config.env).init, jax.random.key(0), obs), params)


def sampling_policy(network: nn.Module, params) -> Policy:
    """The episode-runner policy that samples the network's action distribution at every step."""
    return lambda key, obs, t: network.apply(params, obs)[0].sample(key)


MIRROR_MODES = ("mean", "geometric", "value")
"""How `mirror_policy` joins the policy's views of a level and of its mirror image: the mean of the two action
probabilities, their geometric mean, or the view whose value (the critic's estimate) is higher."""


def mirror_joined(network: nn.Module, params, pair, mode: str) -> Distribution:
    """The action distribution of the policy's view of a level joined with its view of the level's mirror image,
    mirrored back (`MIRROR_MODES`); `pair` is (observation, observation of the mirrored state). Left-right
    equivariant by construction: swapping the pair gives the mirror of the result."""
    return _joined(network.apply(params, pair[0]), network.apply(params, pair[1]), mode)[0]


def _joined(view, mirror_view, mode: str):
    """(distribution, value) of two views (each the network's (distribution, value)) joined in `mode`."""
    (dist, value), (twin, twin_value) = view, mirror_view
    twin = mirrored(twin)
    if mode == "value":
        return chosen(value >= twin_value, dist, twin), jnp.maximum(value, twin_value)
    return averaged(dist, twin, geometric=mode == "geometric"), 0.5 * (value + twin_value)


@dataclasses.dataclass(frozen=True)
class MirrorJoinedNetwork:
    """A plain actor-critic `base` joined with its own view of each state's mirror image (`model.mirror`): it reads
    the pairs of `env.mirror.MirrorPairEnv`, and its action distribution is `mirror_joined`'s in `mode` ('mean' or
    'geometric'), its value the mean of the two views'. Its parameters are `base`'s (the same `init` and tree), so
    plain checkpoints and agents load into it and out of it. Left-right equivariant, in training too."""

    base: nn.Module
    mode: str

    def init(self, key: jax.Array, pair):
        return self.base.init(key, pair[0])

    def apply(self, params, pair):
        return _joined(self.base.apply(params, pair[0]), self.base.apply(params, pair[1]), self.mode)


@dataclasses.dataclass(frozen=True)
class MixedPrecisionNetwork:
    """A plain actor-critic `base` whose layers compute in `compute` (`model.compute`, e.g. bfloat16): `apply` casts
    the float32 parameters and the observation's floats to it and the outputs (distribution, value) back to float32.
    The parameters stay float32 (the same `init` and tree), so the optimiser updates float32 weights with float32
    gradients (the casts' gradients), and checkpoints and agents are the plain model's."""

    base: nn.Module
    compute: jnp.dtype

    def init(self, key: jax.Array, obs):
        return self.base.init(key, obs)

    def apply(self, params, obs):
        dist, value = self.base.apply(_floats_as(params, self.compute), _floats_as(obs, self.compute))
        return _floats_as(dist, jnp.float32), value.astype(jnp.float32)


def _floats_as(tree, dtype):
    """`tree` with its floating-point leaves cast to `dtype` (integer and boolean leaves as they are)."""
    return jax.tree.map(lambda x: x.astype(dtype) if jnp.issubdtype(x.dtype, jnp.floating) else x, tree)


@dataclasses.dataclass(frozen=True)
class FirstViewNetwork:
    """A plain actor-critic `base` that reads the pairs of `env.mirror.MirrorPairEnv` and acts on the first view,
    the state as it is: what a run with the symmetry loss (`ppo.mirror_coef`) trains. Applied to the swapped pair
    it gives its view of the mirror image, which `ppo.ppo_loss` compares with the first. Its parameters are
    `base`'s, so its checkpoints are plain agents."""

    base: nn.Module

    def init(self, key: jax.Array, pair):
        return self.base.init(key, pair[0])

    def apply(self, params, pair):
        return self.base.apply(params, pair[0])


def training_network(config: ExperimentConfig) -> nn.Module:
    """The network a run trains: `make_network`'s, reading observation pairs when the run has the symmetry loss
    (the environment then observes pairs too: `ExperimentConfig.trains_on_pairs`)."""
    network = make_network(config.model, config.env)
    return FirstViewNetwork(network) if config.ppo.mirror_coef else network


def mirror_policy(network: nn.Module, params, mode: str) -> Policy:
    """The episode-runner policy that samples `mirror_joined`: it reads the observation pairs of
    `env.mirror.MirrorPairEnv` and runs the network twice a step."""
    if mode not in MIRROR_MODES:
        raise ValueError(f"unknown mirror mode {mode!r}; choose one of {', '.join(MIRROR_MODES)}")
    return lambda key, pair, t: mirror_joined(network, params, pair, mode).sample(key)


POLICY_HEAD = "actor_head"
"""The parameter scope of every model's policy output layer (`ActorCriticHeads`)."""
CRITIC = ("critic", "critic_head")
"""The parameter scopes of every model's critic: its MLP and its output layer (`ActorCriticHeads`)."""


def replace_subtrees(params: dict, fresh: dict, name: str) -> dict:
    """`params` with every subtree called `name` taken from `fresh` (a tree of the same structure)."""
    flat, fresh_flat = traverse_util.flatten_dict(params), traverse_util.flatten_dict(fresh)
    return traverse_util.unflatten_dict({path: fresh_flat[path] if name in path else v for path, v in flat.items()})


def temper(params: dict, temperature: float) -> dict:
    """`params` with the policy's output layer divided by `temperature`, so its action logits are too: above 1 the
    policy is softer (more exploring), below 1 greedier. Other layers are unchanged."""
    scaled = jax.tree.map(lambda x: (x / temperature).astype(x.dtype), params)
    return replace_subtrees(params, scaled, POLICY_HEAD)


def parameter_count(params) -> int:
    """Number of scalars in a parameter pytree."""
    return sum(x.size for x in jax.tree.leaves(params))
