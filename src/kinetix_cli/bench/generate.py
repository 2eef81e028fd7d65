"""`kinetix bench generate`: kept levels per second of the generator with the default filters, and the compile
times of the sampler alone and of sampler + filters."""

from __future__ import annotations

import dataclasses
import time

import jax

from engine import SIZES
from kinetix_cli.env.level import level_count
from kinetix_cli.generator.filters import generate_chunk, make_config, sample_and_filter_chunks
from kinetix_cli.generator.sampler import sample_level


@dataclasses.dataclass(frozen=True)
class GenerateBenchConfig:
    """What to measure for `kinetix bench generate`.

    Attributes:
        size: 's', 'm' or 'l'.
        chunk: levels sampled per device batch.
        min_time: seconds of timed chunks after compilation.
        seed: generation seed.
    """

    size: str = "s"
    chunk: int = 1024
    min_time: float = 10.0
    seed: int = 0


@dataclasses.dataclass
class GenerateBenchResult:
    """Generation throughput with the default filters (no-op and random), after compilation.

    Attributes:
        sampler_compile_s: compile time of the batched sampler alone [s].
        compile_s: compile time of sampler + filters (what `kinetix generate` compiles) [s].
        sampled_per_s, kept_per_s: levels per second over the timed chunks.
        kept_fraction: kept / sampled.
        chunks: timed chunks.
    """

    size: str
    chunk: int
    sampler_compile_s: float
    compile_s: float
    sampled_per_s: float
    kept_per_s: float
    kept_fraction: float
    chunks: int


def bench_generate(config: GenerateBenchConfig) -> GenerateBenchResult:
    """Compile the sampler and the filters, then generate chunks for at least `min_time` seconds."""
    generation = make_config(config.size, config.chunk)
    static = SIZES[config.size]
    keys = jax.random.split(jax.random.key(config.seed), config.chunk)
    start = time.perf_counter()
    jax.jit(jax.vmap(lambda k: sample_level(static, generation.sampler, k))).lower(keys).compile()
    sampler_compile_s = time.perf_counter() - start
    start = time.perf_counter()
    sample_and_filter_chunks.lower(static, generation.sampler, generation.filters, config.chunk, keys[:1]).compile()
    compile_s = time.perf_counter() - start
    generate_chunk(generation, config.seed, 0)  # warm-up (also loads the compiled function)
    kept = sampled = chunks = 0
    start = time.perf_counter()
    while chunks < 2 or time.perf_counter() - start < config.min_time:
        chunks += 1
        levels, stats = generate_chunk(generation, config.seed, chunks)
        kept += level_count(levels)
        sampled += stats["sampled"]
    elapsed = time.perf_counter() - start
    return GenerateBenchResult(
        config.size,
        config.chunk,
        sampler_compile_s,
        compile_s,
        sampled / elapsed,
        kept / elapsed,
        kept / sampled,
        chunks,
    )
