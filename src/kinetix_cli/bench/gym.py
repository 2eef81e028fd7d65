"""`kinetix bench gym`: what the gymnax and Gymnasium interfaces cost against `KinetixEnv` itself.

Four ways to step the same environments (one level pool, random actions, auto-reset from the pool):
- `KinetixEnv`: `KinetixEnv.step` with a level drawn from the pool, vmapped, `steps` steps per jitted scan;
- `gymnax`: `KinetixGymnax.step`, vmapped, `steps` steps per jitted scan (what a JAX training loop does);
- `gymnax-per-step`: one jitted, vmapped `KinetixGymnax.step` per Python call, results left on the device;
- `gymnasium`: `KinetixVectorEnv.step` per Python call, numpy actions in and numpy results out.
gymnax against KinetixEnv is the interface's own cost; gymnasium against gymnax-per-step is the host-device copy.
"""

from __future__ import annotations

import dataclasses
import statistics
import time
from collections.abc import Callable

import jax
import jax.numpy as jnp
import numpy as np

from kinetix_cli.bench.timing import time_keyed
from kinetix_cli.env.level import index_level
from kinetix_cli.gym import KinetixVectorEnv, make


@dataclasses.dataclass(frozen=True)
class GymBenchConfig:
    """Settings of `kinetix bench gym`.

    Attributes:
        levels: the level source (`kinetix_cli.gym.make`'s `levels`).
        observation: observation type.
        envs: batch sizes.
        steps: environment steps per timed scan (the first two paths).
        min_time: seconds of timed calls per measurement.
        seed: seed of the resets and actions.
    """

    levels: str = "s"
    observation: str = "symbolic-flat"
    envs: tuple[int, ...] = (64, 1024)
    steps: int = 32
    min_time: float = 3.0
    seed: int = 0


@dataclasses.dataclass(frozen=True)
class GymBenchResult:
    path: str
    observation: str
    envs: int
    compile_s: float
    steps_per_s: float
    calls: int


def bench_gym(config: GymBenchConfig, report: Callable[[GymBenchResult], None] = lambda r: None):
    """Measure every path at every batch size; calls `report` after each measurement."""
    env, params = make(config.levels, observation=config.observation)
    results = []
    for envs in config.envs:
        for result in _at(env, params, envs, config):
            report(result)
            results.append(result)
    return results


def _at(env, params, envs: int, config: GymBenchConfig):
    """The four paths at one batch size (a generator: each result as soon as it is measured)."""
    space = env.action_space(params)
    keys = jax.random.split(jax.random.key(config.seed), envs)
    obs, states = jax.jit(jax.vmap(env.reset, in_axes=(0, None)))(keys, params)
    carry = (states, obs, jnp.zeros(envs, jnp.float32))
    step_keys = jax.random.split(jax.random.key(config.seed + 1), envs)

    def direct(carry, key):
        state, _, returns = carry
        k_act, k_level = jax.random.split(key)
        level = index_level(params.pool, jax.random.randint(k_level, (), 0, params.pool_count))
        obs, state, reward, *_ = env.env.step(state, space.sample(k_act), params.env_params, level)
        return state, obs, returns + reward

    def gymnax(carry, key):
        state, _, returns = carry
        k_act, k_step = jax.random.split(key)
        obs, state, reward, *_ = env.step(k_step, state, space.sample(k_act), params)
        return state, obs, returns + reward

    for path, step in (("KinetixEnv", direct), ("gymnax", gymnax)):
        compile_s, rate, calls = time_keyed(step, carry, step_keys, config.steps, config.min_time)
        yield GymBenchResult(path, config.observation, envs, compile_s, rate, calls)

    actions = np.asarray(jax.vmap(space.sample)(jax.random.split(jax.random.key(config.seed + 2), envs)))
    batched = jax.jit(jax.vmap(env.step, in_axes=(0, 0, 0, None)))

    def on_device(state, key):
        return batched(jax.random.split(key, envs), state, jnp.asarray(actions), params)[1]

    yield _per_call("gymnax-per-step", config, envs, states, on_device)
    vector = KinetixVectorEnv(envs, levels=config.levels, observation=config.observation)
    vector.reset(seed=config.seed)

    def through_numpy(_, key):
        vector.step(actions)

    yield _per_call("gymnasium", config, envs, None, through_numpy)


def _per_call(path: str, config: GymBenchConfig, envs: int, carry, call: Callable) -> GymBenchResult:
    """Time `call(carry, key) -> carry` one environment step per call; the first call (compile) apart."""
    key = jax.random.key(config.seed + 3)
    start = time.perf_counter()
    carry = jax.block_until_ready(call(carry, key))
    compile_s = time.perf_counter() - start
    rates, spent = [], 0.0
    while len(rates) < 5 or spent < config.min_time:
        key, now = jax.random.split(key)
        start = time.perf_counter()
        carry = jax.block_until_ready(call(carry, now))
        elapsed = time.perf_counter() - start
        spent += elapsed
        rates.append(envs / elapsed)
    return GymBenchResult(path, config.observation, envs, compile_s, statistics.median(rates), len(rates))
