"""A level's stored solution and the open-loop baselines it is checked against.

A level file's solution is run-length encoded multi-discrete actions:

    "solution": {"actions": [[[1, 0, 0, 0, 0, 0], 40], [[0, 0, 0, 0, 1, 0], 25]]}

each entry an action (see `kinetix_cli.env.actions`) and how many environment steps to hold it; after the
last entry the no-op action is held. `check_level` replays the solution, a no-op policy and random policies
with the one episode runner (`kinetix_cli.env.episode`). Solutions are recorded at the default environment
settings (frame skip 2, 256 steps), with the level's own engine constants.

Examples:
    Motor binding 0 forward for 2 steps, then thruster binding 0 for 1; no-ops fill a horizon of 4 steps:

    >>> solution = {"actions": [[[1, 0, 0, 0, 0, 0], 2], [[0, 0, 0, 0, 1, 0], 1]]}
    >>> actions = decode_solution(solution, "level.json", horizon=4)
    >>> actions
    array([[1, 0, 0, 0, 0, 0],
           [1, 0, 0, 0, 0, 0],
           [0, 0, 0, 0, 1, 0],
           [0, 0, 0, 0, 0, 0]], dtype=int32)
    >>> encode_solution(actions, length=4) == solution
    True
"""

from __future__ import annotations

import jax
import numpy as np

from kinetix_cli.config import EnvSettings
from kinetix_cli.constants import ACTION_WIDTH, NUM_MOTOR_BINDINGS
from kinetix_cli.env.actions import action_space
from kinetix_cli.env.episode import Outcome, replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import Level
from kinetix_cli.errors import LevelError, UserError
from kinetix_cli.levels.parse import LevelSpec

OPEN_LOOP_POLICIES = ("noop", "random", "solution")
"""Policies that need no network: press nothing, uniformly random multi-discrete actions, the stored solution."""
SOLUTION_SETTINGS = EnvSettings(observation="symbolic-flat")
"""The environment settings solutions are recorded and replayed at (the size is each level's own)."""


def decode_solution(solution: dict, source: str, horizon: int) -> np.ndarray:
    """(horizon, 6) int32 actions from a level file's solution record (no-op padded)."""
    space = action_space("multi-discrete")
    entries = solution.get("actions") if isinstance(solution, dict) else None
    if not isinstance(entries, list) or not entries:
        raise LevelError(f"{source}: solution: actions: must be a non-empty list of [action, repeat] entries")
    rows = []
    for i, entry in enumerate(entries):
        ok = isinstance(entry, list) and len(entry) == 2 and isinstance(entry[0], list)
        ok = ok and len(entry[0]) == ACTION_WIDTH
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


def random_actions(count: int, horizon: int, seed: int) -> np.ndarray:
    """(count, horizon, 6) int32 uniformly random multi-discrete actions (a seeded numpy generator)."""
    nvec = np.asarray(action_space("multi-discrete").nvec)
    return (np.random.default_rng(seed).random((count, horizon, ACTION_WIDTH)) * nvec).astype(np.int32)


def open_loop_actions(spec: LevelSpec, policy: str, horizon: int, seed: int = 0) -> np.ndarray:
    """(horizon, 6) int32 multi-discrete actions of an open-loop policy (one of `OPEN_LOOP_POLICIES`)."""
    if policy == "noop":
        return np.zeros((horizon, ACTION_WIDTH), np.int32)
    if policy == "random":
        return random_actions(1, horizon, seed)[0]
    if policy == "solution":
        if spec.solution is None:
            raise UserError(f"{spec.source}: solution: the level ships no solution (try --policy random)")
        return decode_solution(spec.solution, spec.source, horizon)
    raise UserError(f"--policy: unknown policy {policy!r}; choose one of {', '.join(OPEN_LOOP_POLICIES)}")


def used_bindings(level: Level) -> np.ndarray:
    """(6,) bool: which action entries drive anything in this level (4 motor then 2 thruster bindings)."""
    j, t = level.physics.joints, level.physics.thrusters
    b = level.bindings
    used = np.zeros(ACTION_WIDTH, bool)
    motor = np.asarray(j.active & j.motor_on & ~j.fixed & ~b.motor_auto)
    used[np.asarray(b.motor)[motor]] = True
    used[NUM_MOTOR_BINDINGS + np.asarray(b.thruster)[np.asarray(t.active)]] = True
    return used


def broadcast(level: Level, count: int) -> Level:
    """`count` copies of one level as a batch."""
    return jax.tree.map(lambda x: np.broadcast_to(x, (count, *np.shape(x))), level)


def check_level(spec: LevelSpec, attempts: int = 0, seed: int = 0) -> dict[str, Outcome]:
    """Replay a level's solution, a no-op policy and (if attempts > 0) uniformly random policies, at the level's
    own size, in one batch.

    Returns outcomes keyed 'solution' (shape (1,), if the level has one), 'noop' ((1,)) and 'random' ((attempts,)).
    """
    env, params = make_env(SOLUTION_SETTINGS, spec.default_static())
    horizon = SOLUTION_SETTINGS.max_steps
    runs = {"noop": np.zeros((1, horizon, ACTION_WIDTH), np.int32)}
    if spec.solution is not None:
        runs["solution"] = decode_solution(spec.solution, spec.source, horizon)[None]
    if attempts:
        runs["random"] = random_actions(attempts, horizon, seed)
    actions = np.concatenate(list(runs.values()))
    outcome = replay(env, params, broadcast(spec.build(env.static), len(actions)), actions)
    ends = np.cumsum([len(a) for a in runs.values()])
    return {
        name: jax.tree.map(lambda x, end=end, n=len(a): x[end - n : end], outcome)
        for (name, a), end in zip(runs.items(), ends, strict=True)
    }
