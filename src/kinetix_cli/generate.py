"""`kinetix generate`: sample levels in chunks on the device, filter out trivial ones, and hand the kept ones
to the level-set writer (`kinetix_cli.levelset`).

A chunk is `chunk` levels sampled from keys fold_in(key(seed), chunk index), so any chunk can be recomputed
alone (the writer relies on this to resume). The filters play whole episodes (the environment's cap) in one
batch: a no-op policy, and `random_attempts` uniformly random multi-discrete policies per level.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from engine import SIZES, Static
from kinetix_cli.actions import noop_action, sample_action
from kinetix_cli.env import EnvConfig, EnvParams
from kinetix_cli.errors import UserError
from kinetix_cli.level import Level
from kinetix_cli.sampler import SamplerConfig, default_config, is_valid, sample_level
from kinetix_cli.solve import run_episode

FILTERS = ("noop", "random")


@dataclasses.dataclass(frozen=True)
class FilterConfig:
    """Which sampled levels are dropped.

    Attributes:
        noop: drop levels a no-op policy solves within one episode.
        random_attempts: random-policy episodes per level (0: no random filter).
        random_max_rate: drop levels whose random episodes solve more than this fraction.
    """

    noop: bool = True
    random_attempts: int = 3
    random_max_rate: float = 0.5

    def __post_init__(self) -> None:
        if self.random_attempts < 0:
            raise UserError(f"--random-attempts must be >= 0, got {self.random_attempts}")
        if not 0.0 <= self.random_max_rate <= 1.0:
            raise UserError(f"--random-max-rate must be in [0, 1], got {self.random_max_rate}")


def parse_filters(text: str) -> tuple[bool, bool]:
    """'noop,random' | 'noop' | 'random' | 'none' -> (noop, random)."""
    names = {name.strip() for name in text.split(",") if name.strip()}
    if names == {"none"}:
        return False, False
    unknown = names - set(FILTERS)
    if unknown or not names:
        raise UserError(
            f"--filter: unknown filter {', '.join(sorted(unknown)) or repr(text)}; use noop, random or none"
        )
    return "noop" in names, "random" in names


@dataclasses.dataclass(frozen=True)
class GenerateConfig:
    """One level set's generation settings (all of it goes into the manifest).

    Attributes:
        size: 's', 'm' or 'l'.
        chunk: levels sampled per device batch.
        sampler: the level distribution.
        filters: what is dropped.
    """

    size: str
    chunk: int
    sampler: SamplerConfig
    filters: FilterConfig

    def settings(self) -> dict:
        """JSON-ready settings for the manifest."""
        return {
            "chunk": self.chunk,
            "sampler": dataclasses.asdict(self.sampler),
            "filters": dataclasses.asdict(self.filters),
        }


def make_config(size: str, chunk: int = 1024, filters: FilterConfig | None = None) -> GenerateConfig:
    """The reference sampler for `size` with the given filters."""
    if size not in SIZES:
        raise UserError(f"--size: unknown size {size!r}; choose one of {', '.join(SIZES)}")
    if chunk < 1:
        raise UserError(f"--chunk must be >= 1, got {chunk}")
    return GenerateConfig(size, chunk, default_config(size), filters or FilterConfig())


@functools.partial(jax.jit, static_argnums=(0, 1, 2, 3))
def sample_and_filter(static: Static, sampler: SamplerConfig, filters: FilterConfig, chunk: int, key: jax.Array):
    """Sample `chunk` levels and play the filter episodes. Returns (levels, valid, noop_solved, random_solved)
    with levels batched (chunk, ...), flags (chunk,) bool and random_solved (chunk,) int32 episodes."""
    k_levels, k_random = jax.random.split(key)
    levels = jax.vmap(functools.partial(sample_level, static, sampler))(jax.random.split(k_levels, chunk))
    valid = jax.vmap(functools.partial(is_valid, static))(levels)
    config, params = EnvConfig(static), EnvParams()
    horizon = int(params.max_steps)
    episodes = jax.vmap(run_episode, in_axes=(None, None, 0, 0))
    noop_solved = jnp.zeros(chunk, bool)
    if filters.noop:
        noop = jnp.broadcast_to(noop_action(config.action), (chunk, horizon, 6))
        noop_solved = episodes(config, params, levels, noop).solved
    random_solved = jnp.zeros(chunk, jnp.int32)
    if filters.random_attempts:
        n = chunk * filters.random_attempts
        keys = jax.random.split(k_random, (n, horizon))
        actions = jax.vmap(jax.vmap(functools.partial(sample_action, config.action)))(keys)
        repeated = jax.tree.map(lambda x: jnp.repeat(x, filters.random_attempts, axis=0), levels)
        solved = episodes(config, params, repeated, actions).solved
        random_solved = solved.reshape(chunk, filters.random_attempts).sum(1)
    return levels, valid, noop_solved, random_solved


def generate_chunk(config: GenerateConfig, seed: int, index: int) -> tuple[Level, dict]:
    """Chunk `index` of the set: its kept levels (numpy, in sample order) and why the others were dropped."""
    key = jax.random.fold_in(jax.random.key(seed), index)
    f = config.filters
    levels, valid, noop_solved, random_solved = jax.device_get(
        sample_and_filter(SIZES[config.size], config.sampler, f, config.chunk, key)
    )
    too_easy = random_solved > f.random_max_rate * f.random_attempts if f.random_attempts else np.zeros_like(valid)
    dropped_invalid = ~valid
    dropped_noop = valid & noop_solved
    dropped_random = valid & ~noop_solved & too_easy
    keep = valid & ~noop_solved & ~too_easy
    stats = {
        "sampled": int(config.chunk),
        "dropped_invalid": int(dropped_invalid.sum()),
        "dropped_noop": int(dropped_noop.sum()),
        "dropped_random": int(dropped_random.sum()),
    }
    return jax.tree.map(lambda x: np.asarray(x)[keep], levels), stats
