"""`kinetix bench env`: environment steps per second (frame skip, reward, observation and auto-reset included)
and compile time, per observation type and batch size, on random full levels of a size."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import jax
import jax.numpy as jnp
import numpy as np

from engine import SIZES, Static, random_scene
from kinetix_cli.bench.timing import time_keyed
from kinetix_cli.config import EnvSettings
from kinetix_cli.constants import NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS, OBSERVATION_TYPES
from kinetix_cli.env.actions import sample_action
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import Bindings, draw_level, make_level, stack_levels
from kinetix_cli.errors import UserError


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
    """`count` random full levels (see `engine.random_scene`) with random bindings, batched."""
    rng = np.random.default_rng(seed)
    levels = []
    for i in range(count):
        physics = random_scene(static, seed * 100_003 + i).build_numpy(static)
        bindings = Bindings(
            motor=rng.integers(0, NUM_MOTOR_BINDINGS, static.num_joints).astype(np.int32),
            motor_auto=rng.uniform(size=static.num_joints) < 0.1,
            thruster=rng.integers(0, NUM_THRUSTER_BINDINGS, static.num_thrusters).astype(np.int32),
        )
        levels.append(make_level(physics, bindings))
    return stack_levels(levels)


def bench_env(config: EnvBenchConfig, report: Callable[[EnvBenchResult], None] = lambda r: None):
    """Measure every observation type and batch size; calls `report` after each measurement."""
    if config.size not in SIZES:
        raise UserError(f"--size: unknown size {config.size!r}; choose one of {', '.join(SIZES)}")
    for kind in config.observations:
        if kind not in OBSERVATION_TYPES:
            raise UserError(f"--obs: unknown observation {kind!r}; choose from {', '.join(OBSERVATION_TYPES)}")
    static = SIZES[config.size]
    pool = random_levels(static, config.distinct_levels, config.seed)
    results = []
    for kind in config.observations:
        env, params = make_env(EnvSettings(size=config.size, observation=kind))
        for envs in config.envs:
            keys = jax.random.split(jax.random.key(config.seed), envs)
            obs, states = jax.jit(jax.vmap(lambda key, env=env: env.reset_to_level(draw_level(pool, key))))(keys)

            def env_step(carry, key, env=env, params=params):
                # The latest observation and the summed reward ride in the carry, as a rollout would keep
                # them; a step whose outputs were dropped would let XLA skip computing them.
                state, _, returns = carry
                k_act, k_step = jax.random.split(key)
                action = sample_action(env.action, k_act)
                obs, state, reward, *_ = env.step(state, action, params, draw_level(pool, k_step))
                return state, obs, returns + reward

            keys = jax.random.split(jax.random.key(config.seed + 1), envs)
            carry = (states, obs, jnp.zeros(envs, jnp.float32))
            compile_s, rate, calls = time_keyed(env_step, carry, keys, config.steps, config.min_time)
            result = EnvBenchResult(kind, config.size, envs, compile_s, rate, calls)
            results.append(result)
            report(result)
    return results
