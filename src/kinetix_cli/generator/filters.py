"""Generation in chunks: sample levels on the device, drop the trivial ones, and hand the kept ones to the level-set
writer (`kinetix_cli.levels.levelset`).

A chunk is `chunk` levels sampled from keys fold_in(key(seed), chunk index), so any chunk can be recomputed
alone (the writer relies on this to resume). The filters play whole episodes with the episode runner at the
default environment settings (`FILTER_SETTINGS`, the environment's cap) in one batch: a no-op policy, and
`random_attempts` uniformly random multi-discrete policies per level.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
from collections.abc import Callable

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh

from engine import SIZES, Params, Static
from kinetix_cli.config import EnvSettings
from kinetix_cli.env.actions import noop_action, sample_action
from kinetix_cli.env.episode import open_loop, run_episode
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import Level
from kinetix_cli.errors import UserError
from kinetix_cli.generator.sampler import SamplerConfig, default_config, is_valid, sample_level
from kinetix_cli.parallel import batch_sharded, make_mesh, replicate, replicated, using
from kinetix_cli.trace_cache import cached_jit

FILTER_SETTINGS = EnvSettings(observation="symbolic-flat")
"""The environment the filter episodes run in (the size is the chunk's; the observation is never computed)."""
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


@cached_jit(static_argnums=(0, 1, 2, 3))
def sample_and_filter_chunks(
    static: Static, sampler: SamplerConfig, filters: FilterConfig, chunk: int, keys: jax.Array
) -> tuple[Level, jax.Array, jax.Array, jax.Array]:
    """`sample_and_filter` of one chunk per key in `keys` (n,), batched (n, chunk, ...). Under a mesh of n
    devices each device computes one chunk, with the program a single device runs for one chunk: so a chunk
    comes out bit for bit the same at any device count (splitting a chunk instead would change the batch width
    of its filter episodes, and with it XLA's rounding)."""
    play = functools.partial(sample_and_filter, static, sampler, filters, chunk)
    return replicated(jax.vmap(play)(batch_sharded(keys)))  # every process gets every chunk


def sample_and_filter(static: Static, sampler: SamplerConfig, filters: FilterConfig, chunk: int, key: jax.Array):
    """Sample `chunk` levels and play the filter episodes. Returns (levels, valid, noop_solved, random_solved)
    with levels batched (chunk, ...), flags (chunk,) bool and random_solved (chunk,) int32 episodes."""
    k_levels, k_random = jax.random.split(key)
    levels = jax.vmap(functools.partial(sample_level, static, sampler))(jax.random.split(k_levels, chunk))
    valid = jax.vmap(functools.partial(is_valid, static))(levels)
    env, params = make_env(FILTER_SETTINGS, static)
    horizon = FILTER_SETTINGS.max_steps

    def solved(levels: Level, actions: jax.Array) -> jax.Array:
        # Sampled levels all run with the engine's default constants: one unbatched copy (as for a single level;
        # see `share_engine_params`) instead of a (chunk,) batch of equal values.
        levels = levels.replace(engine_params=Params())
        in_axes = (Level(physics=0, bindings=0, engine_params=None), 0)
        play = functools.partial(run_episode, env, params, key=jax.random.key(0), horizon=horizon)
        return jax.vmap(lambda level, seq: play(level, open_loop(seq)).solved, in_axes=in_axes)(levels, actions)

    noop_solved = jnp.zeros(chunk, bool)
    if filters.noop:
        noop_solved = solved(
            levels, jnp.broadcast_to(noop_action(env.action), (chunk, horizon, *env.action_space.shape))
        )
    random_solved = jnp.zeros(chunk, jnp.int32)
    if filters.random_attempts:
        n = chunk * filters.random_attempts
        keys = jax.random.split(k_random, (n, horizon))
        actions = jax.vmap(jax.vmap(functools.partial(sample_action, env.action)))(keys)
        repeated = jax.tree.map(lambda x: jnp.repeat(x, filters.random_attempts, axis=0), levels)
        random_solved = solved(repeated, actions).reshape(chunk, filters.random_attempts).sum(1)
    return levels, valid, noop_solved, random_solved


def generate_chunks(
    config: GenerateConfig, seed: int, indices: range, mesh: Mesh | None = None
) -> list[tuple[Level, dict]]:
    """Chunks `indices` of the set, each as its kept levels (numpy, in sample order) and why the others were
    dropped. With a `mesh`, one chunk per device (`len(indices)` a multiple of the mesh's size), in every
    process of a multi-process run; every process returns every chunk."""
    with using(mesh) if mesh is not None else contextlib.nullcontext():  # keys too: never the caller's mesh
        keys = jax.vmap(lambda i: jax.random.fold_in(jax.random.key(seed), i))(jnp.asarray(indices, jnp.uint32))
        keys = keys if mesh is None else replicate(keys, mesh)
        batch = sample_and_filter_chunks(SIZES[config.size], config.sampler, config.filters, config.chunk, keys)
    batch = jax.device_get(batch)
    return [_kept(config, jax.tree.map(functools.partial(_row, row=row), batch)) for row in range(len(indices))]


def _row(x: np.ndarray, row: int) -> np.ndarray:
    return x[row]


def generate_chunk(config: GenerateConfig, seed: int, index: int) -> tuple[Level, dict]:
    """Chunk `index` of the set on this process's first device: the program `kinetix generate` runs on one device
    (see `generate_chunks`)."""
    return generate_chunks(config, seed, range(index, index + 1), make_mesh(1, local_only=True))[0]


def chunk_source(config: GenerateConfig, seed: int, mesh: Mesh | None = None) -> Callable[[int], tuple[Level, dict]]:
    """`chunk(i)` for a caller that asks for chunks 0, 1, 2, ... in order: computed `mesh.size` at a time (one
    per device), from the chunk asked for on."""
    count = 1 if mesh is None else mesh.size
    ready: dict[int, tuple[Level, dict]] = {}

    def chunk(index: int) -> tuple[Level, dict]:
        if index not in ready:
            ready.clear()
            indices = range(index, index + count)
            ready.update(zip(indices, generate_chunks(config, seed, indices, mesh), strict=True))
        return ready[index]

    return chunk


def _kept(config: GenerateConfig, chunk) -> tuple[Level, dict]:
    """A chunk's kept levels and counters, from `sample_and_filter`'s outputs (host arrays)."""
    levels, valid, noop_solved, random_solved = chunk
    f = config.filters
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
