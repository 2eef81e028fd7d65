"""`kinetix bench engine`: steady-state engine steps per second and compile time, ours and Jax2D's.

Both engines step the same random scenes (filled to the size's capacity, see `engine.random_scenes`)
with the same per-scene actions, at equal solver iterations, in this process. A measurement is one
jitted `scan` over `steps` vmapped steps; it is repeated for at least `min_time` seconds and the median
rate is reported. Compile time (lowering + XLA compile) is reported apart.
"""

from __future__ import annotations

import dataclasses
import datetime
import os
import platform
import statistics
import time
from collections.abc import Callable
from importlib import metadata

import jax
import jax.numpy as jnp
import numpy as np

from engine import SIZES, Params, Static, step
from engine.random_scenes import random_actions, random_scene
from engine.scene import stack
from kinetix_cli.errors import UserError

BENCH_FORMAT = "kinetix-bench/1"


@dataclasses.dataclass(frozen=True)
class EngineBenchConfig:
    """What to measure.

    Attributes:
        size: 's', 'm' or 'l'.
        envs: batch sizes (scenes stepped in parallel).
        against: 'jax2d' to measure the reference engine on the same scenes, or None.
        steps: engine steps per timed call.
        min_time: seconds of timed calls per measurement (at least 2 calls).
        distinct_scenes: distinct random scenes; larger batches repeat them.
        seed: seed of the scenes and actions.
    """

    size: str = "s"
    envs: tuple[int, ...] = (1, 64, 1024, 4096)
    against: str | None = None
    steps: int = 20
    min_time: float = 2.0
    distinct_scenes: int = 128
    seed: int = 0


@dataclasses.dataclass
class BenchResult:
    """One measurement: `steps_per_s` counts single-scene steps (batch x steps / second)."""

    engine: str
    size: str
    envs: int
    compile_s: float
    steps_per_s: float
    calls: int


def time_calls(fn: Callable, carry: tuple, steps_per_call: int, min_time: float) -> tuple[float, float, int]:
    """Compile `fn(*carry) -> carry` and call it repeatedly for at least `min_time` seconds (after a warm-up
    call). Returns (compile seconds, median steps/s, timed calls)."""
    start = time.perf_counter()
    compiled = jax.jit(fn).lower(*carry).compile()
    compile_s = time.perf_counter() - start
    carry = jax.block_until_ready(compiled(*carry))
    rates, spent = [], 0.0
    while len(rates) < 2 or spent < min_time:
        start = time.perf_counter()
        carry = jax.block_until_ready(compiled(*carry))
        elapsed = time.perf_counter() - start
        spent += elapsed
        rates.append(steps_per_call / elapsed)
    return compile_s, statistics.median(rates), len(rates)


def time_stepper(step_fn: Callable, states, actions, steps: int, min_time: float) -> tuple[float, float, int]:
    """Time `scan(vmap(step_fn))` over `steps` steps with fixed per-scene actions."""

    def rollout(states, actions):
        def body(s, _):
            return jax.vmap(step_fn)(s, actions), None

        return jax.lax.scan(body, states, None, length=steps)[0], actions

    return time_calls(rollout, (states, actions), actions.shape[0] * steps, min_time)


def _ours(static: Static):
    params = Params()

    def fn(state, action):
        return step(static, params, state, action)[0]

    return fn


def _jax2d(static: Static):
    from kinetix_cli.jax2d_compat import jax2d_engine

    engine_step, params = jax2d_engine(static)

    def fn(state, action):
        return engine_step(state, params, action)[0]

    return fn


def _tile(tree, batch: int):
    def tile(x):
        reps = -(-batch // x.shape[0])
        return np.concatenate([np.asarray(x)] * reps)[:batch]

    return jax.tree.map(tile, tree)


def bench_engine(
    config: EngineBenchConfig, report: Callable[[BenchResult], None] = lambda r: None
) -> list[BenchResult]:
    """Measure every batch size in `config.envs`; calls `report` after each measurement."""
    if config.size not in SIZES:
        raise UserError(f"--size: unknown size {config.size!r}; choose one of {', '.join(SIZES)}")
    if not config.envs or any(e < 1 for e in config.envs):
        raise UserError(f"--envs: batch sizes must be positive integers, got {config.envs}")
    if config.against not in (None, "jax2d"):
        raise UserError(f"--against: only 'jax2d' is supported, got {config.against!r}")
    static = SIZES[config.size]
    distinct = min(max(config.envs), config.distinct_scenes)
    scenes = [random_scene(static, config.seed * 100_003 + i) for i in range(distinct)]
    all_actions = random_actions(static, np.random.default_rng(config.seed), max(config.envs))
    ours = stack([s.build_numpy(static) for s in scenes])
    engines = [("kinetix", _ours(static), ours)]
    if config.against == "jax2d":
        from kinetix_cli.jax2d_compat import Jax2DMissing, build_jax2d_state

        try:
            reference = stack([build_jax2d_state(s, static) for s in scenes])
            engines.append(("jax2d", _jax2d(static), reference))
        except Jax2DMissing as exc:
            raise UserError(f"--against jax2d: {exc}") from None

    results = []
    for envs in config.envs:
        actions = jax.numpy.asarray(all_actions[:envs])
        for name, fn, states in engines:
            batch = jax.tree.map(jax.numpy.asarray, _tile(states, envs))
            compile_s, rate, calls = time_stepper(fn, batch, actions, config.steps, config.min_time)
            result = BenchResult(name, config.size, envs, compile_s, rate, calls)
            results.append(result)
            report(result)
    return results


@dataclasses.dataclass(frozen=True)
class EnvBenchConfig:
    """What to measure for `kinetix bench env`.

    Attributes:
        size: 's', 'm' or 'l'.
        envs: batch sizes (environments stepped in parallel).
        observations: observation types to measure.
        steps: environment steps per timed call.
        min_time: seconds of timed calls per measurement.
        distinct_levels: random full levels in the reset pool (episodes restart from a random one).
        seed: seed of the levels, bindings and actions.
    """

    size: str = "s"
    envs: tuple[int, ...] = (64, 1024)
    observations: tuple[str, ...] = ("symbolic-flat", "symbolic-entity", "pixels")
    steps: int = 32
    min_time: float = 2.0
    distinct_levels: int = 128
    seed: int = 0


@dataclasses.dataclass
class EnvBenchResult:
    """One measurement: environment steps per second (frame skip, reward, observation, auto-reset and
    random action sampling included)."""

    observation: str
    size: str
    envs: int
    compile_s: float
    steps_per_s: float
    calls: int


def random_levels(static: Static, count: int, seed: int):
    """`count` random full levels (see `engine.random_scenes`) with random bindings, batched."""
    from kinetix_cli.level import Bindings, Level, stack_levels

    rng = np.random.default_rng(seed)
    levels = []
    for i in range(count):
        physics = random_scene(static, seed * 100_003 + i).build_numpy(static)
        bindings = Bindings(
            motor=rng.integers(0, 4, static.num_joints).astype(np.int32),
            motor_auto=rng.uniform(size=static.num_joints) < 0.1,
            thruster=rng.integers(0, 2, static.num_thrusters).astype(np.int32),
        )
        levels.append(Level(physics, bindings))
    return stack_levels(levels)


def bench_env(config: EnvBenchConfig, report: Callable[[EnvBenchResult], None] = lambda r: None):
    """Measure every observation type and batch size; calls `report` after each measurement."""
    from kinetix_cli.actions import sample_action
    from kinetix_cli.env import OBSERVATION_TYPES, EnvConfig, EnvParams, KinetixEnv, reset_from_pool

    if config.size not in SIZES:
        raise UserError(f"--size: unknown size {config.size!r}; choose one of {', '.join(SIZES)}")
    for kind in config.observations:
        if kind not in OBSERVATION_TYPES:
            raise UserError(f"--obs: unknown observation {kind!r}; choose from {', '.join(OBSERVATION_TYPES)}")
    static = SIZES[config.size]
    pool = random_levels(static, config.distinct_levels, config.seed)
    params = EnvParams()
    results = []
    for kind in config.observations:
        env = KinetixEnv(EnvConfig(static, observation=kind), reset_from_pool(pool))
        for envs in config.envs:
            keys = jax.random.split(jax.random.key(config.seed), envs)
            obs, states = jax.vmap(env.reset, in_axes=(0, None))(keys, params)

            def env_step(carry, key, env=env):
                # The latest observation and the summed reward ride in the carry, as a rollout would keep
                # them; a step whose outputs were dropped would let XLA skip computing them.
                state, _, returns = carry
                k_act, k_step = jax.random.split(key)
                action = sample_action(env.config.action, k_act)
                obs, state, reward, _, _ = env.step(k_step, state, action, params)
                return state, obs, returns + reward

            keys = jax.random.split(jax.random.key(config.seed + 1), envs)
            carry = (states, obs, jnp.zeros(envs, jnp.float32))
            compile_s, rate, calls = time_keyed(env_step, carry, keys, config.steps, config.min_time)
            result = EnvBenchResult(kind, config.size, envs, compile_s, rate, calls)
            results.append(result)
            report(result)
    return results


def time_keyed(step_fn: Callable, carry, keys, steps: int, min_time: float) -> tuple[float, float, int]:
    """Time `scan(vmap(step_fn(carry, key)))` with a fresh random key per scene and step; `carry` is batched."""

    def rollout(carry, keys):
        def body(both, _):
            carry, keys = both
            split = jax.vmap(jax.random.split)(keys)
            return (jax.vmap(step_fn)(carry, split[:, 0]), split[:, 1]), None

        return jax.lax.scan(body, (carry, keys), None, length=steps)[0]

    return time_calls(rollout, (carry, keys), keys.shape[0] * steps, min_time)


def environment_info() -> dict:
    """Machine, device and library versions, for the record."""
    versions = {}
    for package in ("jax", "jaxlib", "flax", "numpy", "jax2d"):
        try:
            versions[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            versions[package] = None
    device = jax.devices()[0]
    return {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "machine": {
            "platform": platform.platform(),
            "processor": platform.processor() or platform.machine(),
            "cpu_count": os.cpu_count(),
            "device": f"{device.platform}:{device.device_kind}",
        },
        "versions": versions,
    }


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
    from kinetix_cli.generate import generate_chunk, make_config, sample_and_filter
    from kinetix_cli.sampler import sample_level

    generation = make_config(config.size, config.chunk)
    static = SIZES[config.size]
    keys = jax.random.split(jax.random.key(config.seed), config.chunk)
    start = time.perf_counter()
    jax.jit(jax.vmap(lambda k: sample_level(static, generation.sampler, k))).lower(keys).compile()
    sampler_compile_s = time.perf_counter() - start
    start = time.perf_counter()
    sample_and_filter.lower(static, generation.sampler, generation.filters, config.chunk, keys[0]).compile()
    compile_s = time.perf_counter() - start
    generate_chunk(generation, config.seed, 0)  # warm-up (also loads the compiled function)
    kept = sampled = chunks = 0
    start = time.perf_counter()
    while chunks < 2 or time.perf_counter() - start < config.min_time:
        chunks += 1
        levels, stats = generate_chunk(generation, config.seed, chunks)
        kept += levels.bindings.motor.shape[0]
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
