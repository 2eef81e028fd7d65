"""`kinetix bench engine`: steady-state engine steps per second and compile time, ours and Jax2D's.

Both engines step the same random scenes (filled to the size's capacity, see `engine.random_scene`)
with the same per-scene actions, at equal solver iterations, in this process. A measurement is one
jitted `scan` over `steps` vmapped steps; it is repeated for at least `min_time` seconds and the median
rate is reported. Compile time (lowering + XLA compile) is reported apart.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import jax
import numpy as np

import engine
from engine import SIZES, Params, Static, random_actions, random_scene, stack
from kinetix_cli.bench.jax2d import Jax2DMissing, build_jax2d_state, jax2d_engine
from kinetix_cli.bench.timing import time_calls
from kinetix_cli.errors import UserError


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
        return engine.step(static, params, state, action)[0]

    return fn


def _jax2d(static: Static):
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
