"""Find an open-loop action sequence that solves a level: the cross-entropy method over piecewise-constant
multi-discrete sequences, run on the vmapped environment with the episode runner (`env.episode.replay`).

`kinetix solve LEVEL` keeps only sequences that also solve the level when every movable body starts up to
`jitter` metres away (robust to float noise), and stores them as the level's solution record
(`kinetix_cli.levels.solution`). The environment is the one solutions are recorded at (`SOLUTION_SETTINGS`).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable

import jax
import numpy as np

from kinetix_cli.constants import ACTION_WIDTH
from kinetix_cli.env.actions import action_space
from kinetix_cli.env.episode import Outcome, replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import Level
from kinetix_cli.levels.parse import LevelSpec
from kinetix_cli.levels.solution import SOLUTION_SETTINGS, broadcast, encode_solution, used_bindings


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
    env, params = make_env(SOLUTION_SETTINGS, spec.default_static())
    horizon = SOLUTION_SETTINGS.max_steps
    level = spec.build(env.static)
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
        outcome = replay(env, params, levels, sequences)
        episodes += config.population
        score = fitness(outcome, horizon)
        order = np.argsort(-score)
        if report:
            report(iteration, float(score[order[0]]), float(np.mean(outcome.solved)))
        for index in order[: min(8, int(np.sum(outcome.solved)))]:
            candidate = sequences[index]
            robust = replay(env, params, checks, np.broadcast_to(candidate, (config.checks, *candidate.shape)))
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
