"""Action distributions of the policies: small pure pytrees (no distrax), one per action type.

Every distribution holds arrays with any leading batch shape ``...`` and answers per batch entry:
`sample(key)`, `log_prob(action)`, `entropy()` and `mode()`; `kl_divergence(a, b)` compares two of one type.
Actions follow `kinetix_cli.actions`:

- `MultiCategorical` for ``multi-discrete``: int32 (..., 6), entry i in [0, nvec[i]) with nvec (3, 3, 3, 3, 2, 2).
- `Categorical` for ``discrete``: int32 (...,) in [0, 11).
- `DiagGaussian` for ``continuous``: float32 (..., 6), unbounded (the environment clips).

Impossible choices carry the logit -inf. Entropies and gradients stay finite: the p log p terms of those
choices are replaced by 0 before the product, so no 0 x inf appears in the forward or backward pass.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
from flax import struct

from kinetix_cli.constants import NUM_MOTOR_BINDINGS
from kinetix_cli.env.mirror import DISCRETE_MIRROR, MULTI_DISCRETE_MIRROR

LOG_2PI = math.log(2.0 * math.pi)
LOG_2 = math.log(2.0)


def _entropy_from_logits(logits: jax.Array) -> jax.Array:
    """(...,) entropy [nats] of categorical logits (..., K); -inf logits count as impossible choices."""
    log_p = jax.nn.log_softmax(logits, axis=-1)
    log_p = jnp.where(jnp.isneginf(logits), 0.0, log_p)
    return -jnp.sum(jnp.exp(log_p) * log_p * ~jnp.isneginf(logits), axis=-1)


def _log_prob_from_logits(logits: jax.Array, action: jax.Array) -> jax.Array:
    """(...,) log-probability of the int choices (...,) under logits (..., K); the batch shapes broadcast."""
    action = jnp.asarray(action, jnp.int32)
    shape = jnp.broadcast_shapes(logits.shape[:-1], action.shape)
    log_p = jnp.broadcast_to(jax.nn.log_softmax(logits, axis=-1), (*shape, logits.shape[-1]))
    return jnp.take_along_axis(log_p, jnp.broadcast_to(action, shape)[..., None], axis=-1)[..., 0]


@struct.dataclass
class Categorical:
    """One choice among K.

    Attributes:
        logits: (..., K) float32 unnormalised log-probabilities; -inf marks an impossible choice.
    """

    logits: jax.Array

    def sample(self, key: jax.Array) -> jax.Array:
        """(...,) int32 choices drawn with `key`."""
        return jax.random.categorical(key, self.logits, axis=-1).astype(jnp.int32)

    def log_prob(self, action: jax.Array) -> jax.Array:
        """(...,) log-probability of int choices (...,)."""
        return _log_prob_from_logits(self.logits, action)

    def entropy(self) -> jax.Array:
        """(...,) entropy [nats]."""
        return _entropy_from_logits(self.logits)

    def mode(self) -> jax.Array:
        """(...,) int32 most likely choice."""
        return jnp.argmax(self.logits, axis=-1).astype(jnp.int32)


@struct.dataclass
class MultiCategorical:
    """E independent choices, entry i among nvec[i], padded to K = max(nvec) choices.

    Attributes:
        logits: (..., E, K) float32; logits[..., i, k] is -inf for k >= nvec[i] (see `from_flat`).
    """

    logits: jax.Array

    @classmethod
    def from_flat(cls, flat: jax.Array, nvec: tuple[int, ...], used: jax.Array | None = None) -> MultiCategorical:
        """From (..., E * K) raw logits: reshaped to (..., E, K), padding entries set to -inf. With `used`
        (..., E) bool, an entry that is not used has only choice 0: it always samples 0 and adds nothing to the
        log-probability or the entropy."""
        k = max(nvec)
        logits = flat.reshape(*flat.shape[:-1], len(nvec), k)
        valid = jnp.arange(k)[None, :] < jnp.asarray(nvec)[:, None]
        if used is not None:
            valid = valid & (used[..., None] | (jnp.arange(k) == 0))
        return cls(jnp.where(valid, logits, -jnp.inf))

    def sample(self, key: jax.Array) -> jax.Array:
        """(..., E) int32 choices drawn with `key`."""
        return jax.random.categorical(key, self.logits, axis=-1).astype(jnp.int32)

    def log_prob(self, action: jax.Array) -> jax.Array:
        """(...,) joint log-probability of int choices (..., E): the sum over entries."""
        return jnp.sum(_log_prob_from_logits(self.logits, action), axis=-1)

    def entropy(self) -> jax.Array:
        """(...,) joint entropy [nats]: the sum over entries."""
        return jnp.sum(_entropy_from_logits(self.logits), axis=-1)

    def mode(self) -> jax.Array:
        """(..., E) int32 most likely choice of every entry."""
        return jnp.argmax(self.logits, axis=-1).astype(jnp.int32)


@struct.dataclass
class DiagGaussian:
    """Independent normal per action entry.

    Attributes:
        mean: (..., D) float32.
        log_std: (..., D) float32 log standard deviation (broadcast to `mean`'s shape).
        used: (..., D) bool or None (all used): entries that are not used still sample but add nothing to the
            log-density or the entropy.
    """

    mean: jax.Array
    log_std: jax.Array
    used: jax.Array | None = None

    def _sum(self, terms: jax.Array) -> jax.Array:
        return jnp.sum(terms if self.used is None else jnp.where(self.used, terms, 0.0), axis=-1)

    def sample(self, key: jax.Array) -> jax.Array:
        """(..., D) float32 draw with `key`."""
        noise = jax.random.normal(key, self.mean.shape, self.mean.dtype)
        return self.mean + jnp.exp(self.log_std) * noise

    def log_prob(self, action: jax.Array) -> jax.Array:
        """(...,) log-density of (..., D) actions, summed over entries."""
        z = (action - self.mean) * jnp.exp(-self.log_std)
        return self._sum(-0.5 * z**2 - self.log_std - 0.5 * LOG_2PI)

    def entropy(self) -> jax.Array:
        """(...,) differential entropy [nats], summed over entries."""
        log_std = jnp.broadcast_to(self.log_std, self.mean.shape)
        return self._sum(0.5 + 0.5 * LOG_2PI + log_std)

    def mode(self) -> jax.Array:
        """(..., D) the mean."""
        return self.mean


Distribution = Categorical | MultiCategorical | DiagGaussian


def mirrored(distribution: Distribution) -> Distribution:
    """The distribution of `env.mirror.mirror_action(a)` for `a` drawn from `distribution`: what a policy that
    chose in a level's mirror image chooses in the level (motor directions swapped, thrusters as they are)."""
    if isinstance(distribution, MultiCategorical):
        motors = jnp.asarray(MULTI_DISCRETE_MIRROR)
        logits = distribution.logits
        return MultiCategorical(logits.at[..., :NUM_MOTOR_BINDINGS, :].set(logits[..., :NUM_MOTOR_BINDINGS, motors]))
    if isinstance(distribution, Categorical):
        return Categorical(distribution.logits[..., jnp.asarray(DISCRETE_MIRROR)])  # the choice map is an involution
    sign = jnp.where(jnp.arange(distribution.mean.shape[-1]) < NUM_MOTOR_BINDINGS, -1.0, 1.0)
    return distribution.replace(mean=distribution.mean * sign)


def averaged(a: Distribution, b: Distribution, geometric: bool = False) -> Distribution:
    """The even mix of two distributions of one type. Categorical choices (and each multi-discrete entry) get the
    mean of their two probabilities, or with `geometric` the normalised geometric mean (the mean of the two
    log-probabilities: where one is near uniform the other decides, softened). A Gaussian gets the mean of the two
    means and of the two log standard deviations either way (one Gaussian, not the two-peaked mixture)."""
    if isinstance(a, DiagGaussian):
        return a.replace(mean=0.5 * (a.mean + b.mean), log_std=0.5 * (a.log_std + b.log_std))
    log_a, log_b = jax.nn.log_softmax(a.logits, axis=-1), jax.nn.log_softmax(b.logits, axis=-1)
    if geometric:
        return type(a)(0.5 * (log_a + log_b))  # unnormalised logits; choices impossible in either stay -inf
    return type(a)(jnp.logaddexp(log_a, log_b) - LOG_2)  # choices impossible in both stay -inf


def chosen(pick_a: jax.Array, a: Distribution, b: Distribution) -> Distribution:
    """`a` where `pick_a` (...,) is true, else `b`."""
    return jax.tree.map(
        lambda x, y: jnp.where(pick_a.reshape(pick_a.shape + (1,) * (x.ndim - pick_a.ndim)), x, y), a, b
    )


def kl_divergence(a: Distribution, b: Distribution) -> jax.Array:
    """(...,) KL(a || b) [nats] of two distributions of one type, summed over the entries of a multi-discrete or
    Gaussian action. Choices impossible in `a` add nothing (choices impossible in `b` alone give inf); entries a
    Gaussian does not use add nothing."""
    if isinstance(a, DiagGaussian):
        var_a, var_b = jnp.exp(2.0 * a.log_std), jnp.exp(2.0 * b.log_std)
        return a._sum(b.log_std - a.log_std + (var_a + (a.mean - b.mean) ** 2) / (2.0 * var_b) - 0.5)
    possible = ~jnp.isneginf(a.logits)
    log_a = jnp.where(possible, jax.nn.log_softmax(a.logits, axis=-1), 0.0)  # no -inf reaches a product
    log_b = jnp.where(possible, jax.nn.log_softmax(b.logits, axis=-1), 0.0)
    kl = jnp.sum(jnp.where(possible, jnp.exp(log_a) * (log_a - log_b), 0.0), axis=-1)
    return jnp.sum(kl, axis=-1) if isinstance(a, MultiCategorical) else kl
