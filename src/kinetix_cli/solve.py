"""Open-loop action sequences for a level: replay them in batch, and find one that solves the level (CEM).

A level's solution is stored in its file as run-length encoded multi-discrete actions::

    "solution": {"actions": [[[1, 0, 0, 0, 0, 0], 40], [[0, 0, 0, 0, 1, 0], 25]]}

each entry an action (see `kinetix_cli.actions`) and how many environment steps to hold it; after the
last entry the no-op action is held. `kinetix solve LEVEL` searches for one with the cross-entropy method
over piecewise-constant action sequences, run on the vmapped environment, and keeps only sequences that
also solve the level when every movable body starts up to `jitter` metres away (robust to float noise).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from collections.abc import Callable

import jax
import jax.numpy as jnp
import numpy as np
from flax import struct

from kinetix_cli.actions import NUM_MOTOR_BINDINGS, action_space
from kinetix_cli.env import EnvConfig, EnvParams, KinetixEnv, reset_to
from kinetix_cli.level import Level
from kinetix_cli.level_file import LevelError, LevelSpec

ACTION_WIDTH = 6


@struct.dataclass
class Outcome:
    """How one episode went (shapes () per episode, a leading axis in batches).

    Attributes:
        solved: the episode ended with green touching blue.
        failed: it ended with green touching red.
        length: environment steps until the end (max_steps if it never ended).
        total_return: summed reward, shaping included.
        min_distance: smallest green-blue distance seen [m].
    """

    solved: jax.Array
    failed: jax.Array
    length: jax.Array
    total_return: jax.Array
    min_distance: jax.Array

    @staticmethod
    def start(state) -> Outcome:
        """Nothing happened yet, from an `EnvState`."""
        return Outcome(jnp.bool_(False), jnp.bool_(False), jnp.int32(0), jnp.float32(0.0), state.distance)

    def after_step(self, done, reward, info: dict) -> Outcome:
        """Count one environment step unless the episode had already ended (`done` before the step)."""
        live = ~done
        return Outcome(
            solved=self.solved | (live & info["solved"]),
            failed=self.failed | (live & info["failed"]),
            length=self.length + live.astype(jnp.int32),
            total_return=self.total_return + jnp.where(live, reward, 0.0),
            min_distance=jnp.where(live, jnp.minimum(self.min_distance, info["distance"]), self.min_distance),
        )


def make_env(spec: LevelSpec, static=None) -> tuple[EnvConfig, EnvParams, Level]:
    """The multi-discrete, symbolic-flat environment config of one level, its params and its device level."""
    level = jax.tree.map(jnp.asarray, spec.build(static))
    config = EnvConfig(static or spec.default_static())
    return config, EnvParams(engine=spec.engine_params()), level


def run_episode(config: EnvConfig, params: EnvParams, level: Level, actions: jax.Array) -> Outcome:
    """Play `actions` (H, 6) from `level` until the episode ends (no auto-reset). Pure; vmap over levels or
    action sequences. Steps after the end are computed but not counted."""
    env = KinetixEnv(config, reset_to(level))
    state = env.state_from_level(level)

    def body(carry, action):
        state, outcome, done = carry
        state, reward, ended, info = env.step_env(state, action, params)
        return (state, outcome.after_step(done, reward, info), done | ended), None

    (_, outcome, _), _ = jax.lax.scan(body, (state, Outcome.start(state), jnp.bool_(False)), actions)
    return outcome


@functools.partial(jax.jit, static_argnums=(0,))
def _batch_episodes(config: EnvConfig, params: EnvParams, levels: Level, actions: jax.Array) -> Outcome:
    return jax.vmap(run_episode, in_axes=(None, None, 0, 0))(config, params, levels, actions)


def play(config: EnvConfig, params: EnvParams, levels: Level, actions) -> Outcome:
    """Batched `run_episode`: levels (B, ...) and actions (B, H, 6); one compile per config and shape."""
    return jax.device_get(_batch_episodes(config, params, levels, jnp.asarray(actions)))


def broadcast(level: Level, count: int) -> Level:
    """`count` copies of one level as a batch."""
    return jax.tree.map(lambda x: jnp.broadcast_to(x, (count, *x.shape)), level)


def jitter_levels(level: Level, key: jax.Array, count: int, jitter: float) -> Level:
    """`count` copies of `level`; copy 0 is exact, the others move every movable body by up to `jitter` m."""
    bodies = level.physics.bodies
    movable = (bodies.active & ~bodies.fixed)[:, None]
    noise = jax.random.uniform(key, (count, *bodies.position.shape), minval=-jitter, maxval=jitter)
    noise = noise.at[0].set(0.0) * movable
    batch = broadcast(level, count)
    return batch.replace(
        physics=batch.physics.replace(bodies=batch.physics.bodies.replace(position=bodies.position + noise))
    )


# --- solution records ---------------------------------------------------------------------------
def decode_solution(solution: dict, source: str, horizon: int) -> np.ndarray:
    """(horizon, 6) int32 actions from a level file's solution record (no-op padded)."""
    space = action_space("multi-discrete")
    entries = solution.get("actions") if isinstance(solution, dict) else None
    if not isinstance(entries, list) or not entries:
        raise LevelError(f"{source}: solution: actions: must be a non-empty list of [action, repeat] entries")
    rows = []
    for i, entry in enumerate(entries):
        ok = isinstance(entry, list) and len(entry) == 2 and isinstance(entry[0], list) and len(entry[0]) == 6
        ok = ok and all(isinstance(v, int) and 0 <= v < n for v, n in zip(entry[0], space.nvec, strict=True))
        if not ok or not isinstance(entry[1], int) or entry[1] < 1:
            raise LevelError(
                f"{source}: solution: actions[{i}]: must be [[m0, m1, m2, m3, t0, t1], repeat >= 1] with motors "
                f"in 0..2 and thrusters in 0..1, got {entry!r}"
            )
        rows += [entry[0]] * entry[1]
    actions = np.zeros((horizon, ACTION_WIDTH), np.int32)
    rows = np.asarray(rows[:horizon], np.int32)
    actions[: len(rows)] = rows
    return actions


def encode_solution(actions: np.ndarray, length: int) -> dict:
    """Run-length encode the first `length` rows of (H, 6) actions; trailing no-ops are dropped."""
    rows = [list(map(int, row)) for row in np.asarray(actions)[:length]]
    while rows and not any(rows[-1]):
        rows.pop()
    entries: list[list] = []
    for row in rows:
        if entries and entries[-1][0] == row:
            entries[-1][1] += 1
        else:
            entries.append([row, 1])
    return {"actions": entries or [[[0] * ACTION_WIDTH, 1]]}


def used_bindings(level: Level) -> np.ndarray:
    """(6,) bool: which action entries drive anything in this level (4 motor then 2 thruster bindings)."""
    j, t = level.physics.joints, level.physics.thrusters
    b = level.bindings
    used = np.zeros(ACTION_WIDTH, bool)
    motor = np.asarray(j.active & j.motor_on & ~j.fixed & ~b.motor_auto)
    used[np.asarray(b.motor)[motor]] = True
    used[NUM_MOTOR_BINDINGS + np.asarray(b.thruster)[np.asarray(t.active)]] = True
    return used


# --- search -------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class SolveConfig:
    """Cross-entropy search over piecewise-constant multi-discrete action sequences.

    Attributes:
        population: sequences tried per iteration.
        elite: fraction of the population that refits the distribution.
        iterations: most iterations.
        segments: pieces of constant action over the episode (each max_steps / segments steps).
        jitter: a solution must also solve `checks` copies of the level with bodies moved up to this [m].
        checks: copies in the robustness check (the first is the exact level).
        smoothing: new probabilities = smoothing * old + (1 - smoothing) * elite frequencies.
        seed: random seed.
    """

    population: int = 256
    elite: float = 0.1
    iterations: int = 20
    segments: int = 16
    jitter: float = 0.002
    checks: int = 8
    smoothing: float = 0.3
    seed: int = 0


@dataclasses.dataclass
class SolveResult:
    """What the search found: `solution` is a solution record (None if nothing robust was found)."""

    solution: dict | None
    length: int
    robust_fraction: float
    iterations: int
    episodes: int
    seconds: float


def fitness(outcome: Outcome, horizon: int) -> np.ndarray:
    """Higher is better: solved episodes by speed, then failures last, else closest approach."""
    solved = np.asarray(outcome.solved)
    return np.where(
        solved,
        1000.0 + horizon - np.asarray(outcome.length),
        np.where(np.asarray(outcome.failed), -1000.0, 0.0) - np.asarray(outcome.min_distance),
    )


def solve(spec: LevelSpec, config: SolveConfig, report: Callable[[int, float, float], None] | None = None):
    """Search for a robust solution of a level. `report(iteration, best fitness, solved fraction)`."""
    env_config, params, level = make_env(spec)
    horizon = int(params.max_steps)
    used = used_bindings(level)
    nvec = np.asarray(action_space("multi-discrete").nvec)
    rng = np.random.default_rng(config.seed)
    probs = np.zeros((config.segments, ACTION_WIDTH, 3))
    probs[:, :, :] = np.where(np.arange(3) < nvec[:, None], 1.0 / nvec[:, None], 0.0)
    probs[:, ~used] = np.array([1.0, 0.0, 0.0])
    repeat = math.ceil(horizon / config.segments)
    levels = broadcast(level, config.population)
    checks = jitter_levels(level, jax.random.key(config.seed), config.checks, config.jitter)
    n_elite = max(2, int(config.elite * config.population))
    start, episodes = time.perf_counter(), 0
    for iteration in range(1, config.iterations + 1):
        cumulative = probs.cumsum(-1)
        draws = rng.random((config.population, config.segments, ACTION_WIDTH, 1))
        pieces = (draws > cumulative).sum(-1).astype(np.int32)
        sequences = np.repeat(pieces, repeat, axis=1)[:, :horizon]
        outcome = play(env_config, params, levels, sequences)
        episodes += config.population
        score = fitness(outcome, horizon)
        order = np.argsort(-score)
        if report:
            report(iteration, float(score[order[0]]), float(np.mean(outcome.solved)))
        for index in order[: min(8, int(np.sum(outcome.solved)))]:
            candidate = sequences[index]
            robust = play(env_config, params, checks, np.broadcast_to(candidate, (config.checks, *candidate.shape)))
            episodes += config.checks
            if bool(np.all(robust.solved)):
                length = int(outcome.length[index])
                return SolveResult(
                    encode_solution(candidate, length), length, 1.0, iteration, episodes, time.perf_counter() - start
                )
        elite = pieces[order[:n_elite]]
        frequencies = (elite[..., None] == np.arange(3)).mean(0)
        probs = config.smoothing * probs + (1 - config.smoothing) * frequencies
    return SolveResult(None, 0, 0.0, config.iterations, episodes, time.perf_counter() - start)


def check_level(spec: LevelSpec, static=None, attempts: int = 0, seed: int = 0) -> dict[str, Outcome]:
    """Replay a level's solution, a no-op policy and (if attempts > 0) uniformly random policies.

    Returns outcomes keyed 'solution' (shape (1,)), 'noop' ((1,)) and 'random' ((attempts,)).
    """
    env_config, params, level = make_env(spec, static)
    horizon = int(params.max_steps)
    result = {}
    if spec.solution is not None:
        actions = decode_solution(spec.solution, spec.path or spec.name, horizon)
        result["solution"] = play(env_config, params, broadcast(level, 1), actions[None])
    result["noop"] = play(env_config, params, broadcast(level, 1), np.zeros((1, horizon, ACTION_WIDTH), np.int32))
    if attempts:
        nvec = np.asarray(action_space("multi-discrete").nvec)
        draws = np.random.default_rng(seed).random((attempts, horizon, ACTION_WIDTH))
        actions = (draws * nvec).astype(np.int32)
        result["random"] = play(env_config, params, broadcast(level, attempts), actions)
    return result
