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
from pathlib import Path

import jax
import numpy as np

from engine import SIZES
from kinetix_cli.constants import ACTION_WIDTH
from kinetix_cli.env.actions import action_space
from kinetix_cli.env.episode import Outcome, replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import Level, index_level, level_count
from kinetix_cli.levels.levelset import Solutions, generate_levelset, load_levelset
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


# --- many levels at once (solved level sets) ------------------------------------------------------
def solve_levels(levels: Level, static, config: SolveConfig) -> Solutions:
    """The same cross-entropy search on a batch of levels of one size at once: every iteration plays
    `config.population` sequences of each unsolved level in one batched replay; a level's search stops at its first
    solving sequence, whose shortest solve is kept. Each solution replays exactly (the environment is deterministic);
    unlike `solve`, no nudged copies are checked (`jitter` and `checks` are not used). `levels` has numpy leaves with
    a leading level axis; the result is deterministic in `config.seed`."""
    env, params = make_env(SOLUTION_SETTINGS, static)
    horizon = SOLUTION_SETTINGS.max_steps
    n, p = level_count(levels), config.population
    nvec = np.asarray(action_space("multi-discrete").nvec)
    start = np.where(np.arange(3) < nvec[:, None], 1.0 / nvec[:, None], 0.0)  # (6, 3) uniform over valid choices
    probs = np.broadcast_to(start, (n, config.segments, ACTION_WIDTH, 3)).copy()
    for i in range(n):  # entries no actuator uses stay off
        probs[i][:, ~used_bindings(index_level(levels, i))] = [1.0, 0.0, 0.0]
    repeat = math.ceil(horizon / config.segments)
    rng = np.random.default_rng(config.seed)
    batch = jax.tree.map(lambda x: np.repeat(np.asarray(x), p, axis=0), levels)  # level i's copies at rows i*p..
    n_elite = max(2, int(config.elite * p))
    found = Solutions(np.zeros((n, horizon, ACTION_WIDTH), np.int8), np.zeros(n, bool), np.zeros(n, np.int32))
    for _ in range(config.iterations):
        draws = rng.random((n, p, config.segments, ACTION_WIDTH, 1))
        pieces = (draws > probs.cumsum(-1)[:, None]).sum(-1).astype(np.int32)  # (n, p, segments, 6)
        sequences = np.repeat(pieces, repeat, axis=2)[:, :, :horizon]
        outcome = replay(env, params, batch, sequences.reshape(n * p, horizon, ACTION_WIDTH))
        score = fitness(outcome, horizon).reshape(n, p)
        solved, length = np.asarray(outcome.solved).reshape(n, p), np.asarray(outcome.length).reshape(n, p)
        for i in np.flatnonzero(~found.solved & solved.any(1)):
            best = int(np.argmax(score[i]))  # solved sequences score highest, the shortest first
            found.solved[i], found.length[i] = True, length[i, best]
            found.actions[i, : length[i, best]] = sequences[i, best, : length[i, best]]
        if found.solved.all():
            break
        elite = np.take_along_axis(pieces, np.argsort(-score, axis=1)[:, :n_elite, None, None], axis=1)
        frequencies = (elite[..., None] == np.arange(3)).mean(1)
        probs = config.smoothing * probs + (1 - config.smoothing) * frequencies
    return found


def solve_levelset(
    source: Path,
    out: Path,
    config: SolveConfig,
    batch: int = 64,
    progress: Callable[[int, dict], None] | None = None,
    shard_size: int | None = None,
) -> dict:
    """Write the solved level set of the set in `source` into `out` (`levelset`'s solved form: every level with its
    search result, the unsolved marked), `batch` levels per search; resumable and byte-reproducible like every set
    (batch k searches with seed `config.seed + k`). A killed solve resumes at its last written shard, every
    `shard_size` levels (default: the source set's). Returns the new set's manifest, whose `stats` count the solved
    and unsolved levels."""
    levelset = load_levelset(source)
    manifest = levelset.manifest
    static = SIZES[manifest["size"]]

    def chunk(k: int):
        rows = jax.tree.map(lambda x: x[k * batch : (k + 1) * batch], levelset.levels)
        found = solve_levels(rows, static, dataclasses.replace(config, seed=config.seed + k))
        solved = int(found.solved.sum())
        return rows, {"solved": solved, "unsolved": len(found.solved) - solved}, found

    search = {key: getattr(config, key) for key in ("population", "elite", "iterations", "segments", "smoothing")}
    origin = {key: manifest[key] for key in ("size", "count", "seed", "settings")}
    settings = {
        "solved_from": origin | {"shards": [shard["sha256"] for shard in manifest["shards"]]},
        "search": search | {"seed": config.seed, "batch": batch},
    }
    return generate_levelset(
        out,
        size=manifest["size"],
        count=manifest["count"],
        seed=manifest["seed"],
        settings=settings,
        chunk_fn=chunk,
        shard_size=manifest["shard_size"] if shard_size is None else shard_size,
        progress=progress,
        solutions=True,
    )
