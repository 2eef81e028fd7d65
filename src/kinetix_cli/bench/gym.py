"""`kinetix bench gym`: what the gymnax and Gymnasium interfaces cost against `KinetixEnv` itself.

Four ways to step the same environments (one level source, random actions, auto-reset from its pool):
- `KinetixEnv`: `KinetixEnv.step` with a level drawn from the pool, vmapped, `steps` steps per jitted scan;
- `gymnax`: `KinetixGymnax.step`, vmapped, `steps` steps per jitted scan (what a JAX training loop does);
- `gymnax-per-step`: one jitted, vmapped `KinetixGymnax.step` per Python call, results left on the device;
- `gymnasium`: `KinetixVectorEnv.step` per Python call, numpy actions in and numpy results out (with fresh levels,
  the batches it draws itself included).
gymnax against KinetixEnv is the interface's own cost; gymnasium against gymnax-per-step is the host-device copy.
With fresh levels (`levels="fresh"`) the scans step on the current batch, and a fifth measurement, `refresh_levels`,
times drawing the next batch (`KinetixGymnax.refresh_levels`): a training loop pays it once per batch.
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
        size: the size levels are built at (`make`'s `size`; None: what the levels need, m for fresh levels).
        observation: observation type.
        envs: batch sizes.
        steps: environment steps per timed scan (the first two paths).
        min_time: seconds of timed calls per measurement.
        seed: seed of the resets and actions.
    """

    levels: str = "s"
    size: str | None = None
    observation: str = "symbolic-flat"
    envs: tuple[int, ...] = (64, 1024)
    steps: int = 32
    min_time: float = 3.0
    seed: int = 0


@dataclasses.dataclass(frozen=True)
class GymBenchResult:
    """One measurement.

    Attributes:
        path: how the environments were stepped (module docstring), or `refresh_levels`.
        observation: observation type.
        envs: environments stepped as one batch; for `refresh_levels`, the levels in a batch.
        compile_s: seconds of the first call (compiling it); for `refresh_levels`, of `make` (compiling the
            sampler and drawing the first batch) [s].
        steps_per_s: median environment steps per second; for `refresh_levels`, levels drawn per second.
        calls: timed calls.
    """

    path: str
    observation: str
    envs: int
    compile_s: float
    steps_per_s: float
    calls: int


def bench_gym(config: GymBenchConfig, report: Callable[[GymBenchResult], None] = lambda r: None):
    """Measure every path at every batch size; calls `report` after each measurement."""
    start = time.perf_counter()
    env, params = make(config.levels, size=config.size, observation=config.observation)
    make_s = time.perf_counter() - start
    results = []
    if env.fresh is not None:
        results.append(_refresh(env, params, config, make_s))
        report(results[-1])
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
    vector = KinetixVectorEnv(envs, levels=config.levels, size=config.size, observation=config.observation)
    vector.reset(seed=config.seed)

    def through_numpy(_, key):
        vector.step(actions)

    yield _per_call("gymnasium", config, envs, None, through_numpy)


def _refresh(env, params, config: GymBenchConfig, make_s: float) -> GymBenchResult:
    """Time `refresh_levels`, one batch per call (`make` compiled it)."""
    levels = int(params.pool_count)

    def call(params, key):
        return env.refresh_levels(key, params)

    return dataclasses.replace(_per_call("refresh_levels", config, levels, params, call), compile_s=make_s)


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
