"""Levels on the fly: a batch of fresh random levels sampled inside a jitted computation (the training step).

The reference samples a whole new level for every environment at every step and keeps it where an episode ended,
which makes its environment ~25x slower than its engine. Here a training update draws one batch of `count` fresh
levels at its start, and the episodes that end during the update restart from levels drawn out of that batch:
every update trains on levels no earlier update has seen, at the cost of one vmapped sampler call per update.

The one filter cheap enough for the graph is `is_valid` (green and blue present, a working actuator, no deep
overlap): `OVERSAMPLE` times `count` candidates are drawn and the valid ones come first. As every sampled level has
measured valid, `OVERSAMPLE` is 1 and the filter is a guard that costs one check per level. The episode filters of
`kinetix generate` (no-op and random play) cost whole rollouts and are left to level sets.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp

from engine import Static
from kinetix_cli.env.level import Level, index_level
from kinetix_cli.generator.sampler import SamplerConfig, default_config, empty_level, is_valid, sample_level

OVERSAMPLE = 1
"""Candidates drawn per fresh level; with more than one, the valid ones are kept first. 1: measured on 2 x 2,048
levels per size (2026-11-25, seeds 0 and 1), every sampled s, m and l level was valid, so more candidates would only
multiply the sampling cost (2,048 levels take 0.39 s at s, 1.1 s at m and 14 s at l on this 2-core CPU)."""


@dataclasses.dataclass(frozen=True)
class FreshLevels:
    """A static (hashable) description of a fresh-level source: the size and the sampler's distribution.

    Call it inside a jitted function: `FreshLevels(static, sampler)(key, count)` -> `count` levels, batched."""

    static: Static
    sampler: SamplerConfig

    @classmethod
    def for_size(cls, static: Static, size: str, like: tuple[str, ...] = ()) -> FreshLevels:
        """The reference distribution of `size` (nothing fixed at size s), or with `like` a mix of levels like
        those sizes in `size`'s slots (`SamplerConfig.like`)."""
        return cls(static, dataclasses.replace(default_config(size), like=tuple(like)))

    def __call__(self, key: jax.Array, count: int) -> Level:
        return fresh_levels(self.static, self.sampler, key, count)

    def placeholder(self) -> Level:
        """A batch of one empty arena: a stand-in with the shapes of real levels, for what must exist before the
        first batch is sampled (initial environment states, network initialisation)."""
        return jax.tree.map(lambda x: jnp.asarray(x)[None], empty_level(self.static))


@functools.partial(jax.jit, static_argnums=(0, 1, 3))
def fresh_levels(static: Static, sampler: SamplerConfig, key: jax.Array, count: int) -> Level:
    """`count` random levels (batched on the leading axis), valid ones first among `OVERSAMPLE * count`
    candidates, in the order they were sampled. Pure; the same key gives the same levels.

    Jitted, so that inside a traced computation it is traced once per size, distribution and count: SFL's update
    and its scoring each draw 128 fresh levels in the shipped recipe, and tracing the sampler was a quarter of a
    cached command's start (`kinetix pretrain` of experiments/general.yaml, compile read from the cache)."""
    candidates = jax.vmap(functools.partial(sample_level, static, sampler))(jax.random.split(key, OVERSAMPLE * count))
    valid = jax.vmap(functools.partial(is_valid, static))(candidates)
    order = jnp.argsort(jnp.logical_not(valid).astype(jnp.int32), stable=True)[:count]
    return index_level(candidates, order)
