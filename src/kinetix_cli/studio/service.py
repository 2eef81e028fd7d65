"""What the level studio does, without HTTP: check a level with the project's parser, generate and mutate levels,
play a level step by step in the real environment, and let a trained agent play it or be evaluated on it.

Every method takes and returns JSON values (the server's request and response bodies). Compiled functions are
kept per size (play) and per agent and size (watch), so a second level of the same size never compiles again.
Play runs at the settings level solutions are recorded at (`SOLUTION_SETTINGS`: frame skip 2, 256 steps), so an
episode kept as a level's solution replays exactly under `kinetix validate --play`.
"""

from __future__ import annotations

import collections
import dataclasses
import json
import os
import re
import secrets
import tempfile
import threading
from pathlib import Path
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from engine import NUM_ARENA_POLYGONS, SIZES, Scene
from kinetix_cli.constants import ACTION_WIDTH, INT32_MAX
from kinetix_cli.env.actions import action_space, binding_values
from kinetix_cli.env.environment import EnvState
from kinetix_cli.env.factory import make_env
from kinetix_cli.errors import LevelError, UserError
from kinetix_cli.generator.fresh import fresh_levels
from kinetix_cli.generator.mutate import mutate_level
from kinetix_cli.generator.sampler import default_config
from kinetix_cli.levels.export import export_level
from kinetix_cli.levels.parse import LevelSpec, parse_level
from kinetix_cli.levels.solution import SOLUTION_SETTINGS, encode_solution
from kinetix_cli.rl.agents import LoadedPolicy, load_policy, shipped_names
from kinetix_cli.rl.evaluate import Evaluator
from kinetix_cli.studio.workspace import StudioError, Workspace
from kinetix_cli.viz.rollout import episode_recorder
from kinetix_cli.viz.scene import describe_scene, scene_json

MAX_PLAYS = 8
"""Play sessions kept at once (the oldest is dropped)."""
MAX_ATTEMPTS = 1000
"""Attempts one evaluation request may ask for."""
MAX_EDITS = 64
"""Edits one mutation request may ask for."""
_ENTITY = re.compile(r"^(bodies|joints|thrusters)\[(\d+)\]")


@dataclasses.dataclass
class _Play:
    spec: LevelSpec
    level: dict  # the level's JSON without its solution, as the episode started
    size: str
    state: EnvState
    actions: list[list[int]]
    total_return: float = 0.0
    ending: str | None = None  # "solved", "failed", "timed out" once the episode is over


class Studio:
    """The studio's state: its folder, compiled functions, play sessions and loaded agents. One lock serialises
    the calls (the server runs requests on a thread pool; the studio has one user)."""

    def __init__(self, root: str | Path) -> None:
        self.workspace = Workspace(root)
        self.lock = threading.Lock()
        self._envs: dict[str, tuple] = {}
        self._plays: collections.OrderedDict[str, _Play] = collections.OrderedDict()
        self._policies: dict[str, LoadedPolicy] = {}
        self._recorders: dict[tuple[str, str], tuple] = {}

    # --- levels -----------------------------------------------------------------------------------------
    def check(self, level: Any) -> dict:
        """Whether `level` is a valid level, as `kinetix validate` says it: {"ok": true, "size", "scene",
        "slots"} (slots: each body's engine slot, to pick bodies on the page), or {"ok": false, "error", "entity",
        "field"}: the parser's one line and, where it names one, the entity (e.g. "bodies[2]") and field."""
        try:
            spec = parse_level(level, "level")
            size = spec.default_size()
            built = spec.build(SIZES[size])
        except LevelError as exc:
            message = str(exc).removeprefix("level: ")
            match = _ENTITY.match(message)
            field = message.split(": ")[1] if match and message.count(": ") >= 2 else None
            return {"ok": False, "error": message, "entity": match.group(0) if match else None, "field": field}
        scene = scene_json(describe_scene(built.physics, built.bindings))
        return {"ok": True, "size": size, "name": spec.name, "scene": scene, "slots": _body_slots(level, size)}

    def generate(self, size: Any, seed: Any) -> dict:
        """A random level of `size` from the generator (the training distribution), as level JSON."""
        size, seed = _size(size), _seed(seed)
        static = SIZES[size]
        level = _fresh(size)(jax.random.key(seed))
        return export_level(
            jax.tree.map(np.asarray, level), static, name=f"random {size} {seed}", description="a generated level"
        )

    def mutate(self, level: Any, seed: Any, edits: Any = 1) -> dict:
        """`level` after `edits` random ACCEL edits (add, move, rotate, resize shapes, swap roles, ...)."""
        spec = self._valid(level)
        seed = _seed(seed)
        if not isinstance(edits, int) or isinstance(edits, bool) or not 1 <= edits <= MAX_EDITS:
            raise StudioError(400, f"edits: expected a whole number in 1..{MAX_EDITS}, got {edits!r}")
        size = spec.default_size()
        built = spec.build(SIZES[size])
        edited = _mutator(size, edits)(jax.random.key(seed), built)
        return export_level(jax.tree.map(np.asarray, edited), SIZES[size], name=spec.name, description=spec.description)

    # --- play -------------------------------------------------------------------------------------------
    def play_start(self, level: Any) -> dict:
        """Start an episode of `level`; returns its id and first frame."""
        spec = self._valid(level)
        size = spec.default_size()
        env, _, _ = self._env(size)
        state = env.initial_state(spec.build(env.static))
        play_id = secrets.token_hex(8)
        self._plays[play_id] = _Play(spec, _unsolved(level), size, state, [])
        while len(self._plays) > MAX_PLAYS:
            self._plays.popitem(last=False)
        return {"play": play_id, **self._frame(self._plays[play_id], np.zeros(ACTION_WIDTH, np.int32), 0.0)}

    def play_step(self, play_id: Any, action: Any, steps: Any = 1) -> dict:
        """`steps` environment steps (1..8) holding `action` (6 multi-discrete entries: motors 0 off, 1 forward,
        2 backward; thrusters 0 off, 1 on); the frame after them. An ended episode stays ended."""
        play = self._play(play_id)
        action = _action(action)
        if not isinstance(steps, int) or isinstance(steps, bool) or not 1 <= steps <= 8:
            raise StudioError(400, f"steps: expected a whole number in 1..8, got {steps!r}")
        env, params, step = self._env(play.size)
        reward = 0.0
        for _ in range(steps):
            if play.ending is not None:
                break
            play.state, r, terminated, truncated, solved, failed = step(play.state, jnp.asarray(action), params)
            play.actions.append(action.tolist())
            reward += float(r)
            if bool(terminated) or bool(truncated):
                play.ending = "solved" if bool(solved) else "failed" if bool(failed) else "timed out"
        play.total_return += reward
        return self._frame(play, action, reward)

    def play_solution(self, play_id: Any, level: Any) -> dict:
        """`level` with the played episode as its solution; only an episode that solved the level."""
        play = self._play(play_id)
        if play.ending != "solved":
            raise StudioError(409, "the episode has not solved the level; only a solving episode can be kept")
        if not isinstance(level, dict) or _unsolved(level) != play.level:
            raise StudioError(409, "the level changed since this episode started; play it again")
        return dict(level) | {"solution": encode_solution(np.asarray(play.actions), len(play.actions))}

    def _frame(self, play: _Play, action: np.ndarray, reward: float) -> dict:
        physics = jax.tree.map(np.asarray, play.state.physics)
        values = np.asarray(binding_values("multi-discrete", jnp.asarray(action)))
        scene = describe_scene(physics, play.state.bindings, values)
        return {
            "scene": scene_json(scene),
            "step": len(play.actions),
            "reward": reward,
            "return": play.total_return,
            "ending": play.ending,
            "seconds": len(play.actions) * SOLUTION_SETTINGS.frame_skip * float(play.spec.engine_params().dt),
        }

    def _play(self, play_id: Any) -> _Play:
        if not isinstance(play_id, str) or play_id not in self._plays:
            raise StudioError(404, "play: no such episode (it ended long ago or the studio restarted); start again")
        return self._plays[play_id]

    def _env(self, size: str) -> tuple:
        """(env, params, jitted step) at the solution settings for `size`, compiled on first use."""
        if size not in self._envs:
            env, params = make_env(SOLUTION_SETTINGS, SIZES[size])

            @jax.jit
            def step(state, action, params):
                _, state, reward, terminated, truncated, info = env.step_env(state, action, params)
                return state, reward, terminated, truncated, info["solved"], info["failed"]

            self._envs[size] = (env, params, step)
        return self._envs[size]

    def warm(self, sizes: tuple[str, ...] = ("s", "m", "l")) -> None:
        """Compile the play step of each size now (a no-op step of an empty scene), so the first key press
        does not wait for it."""
        for size in sizes:
            env, params, step = self._env(size)
            level = LevelSpec("warm", "", size, Scene(), [], [], {}).build(SIZES[size])
            jax.block_until_ready(step(env.initial_state(level), jnp.zeros(ACTION_WIDTH, jnp.int32), params))

    # --- agents -----------------------------------------------------------------------------------------
    def agents(self) -> list[str]:
        return shipped_names()

    def watch(self, level: Any, agent: Any, seed: Any = 0) -> dict:
        """One episode of `agent` (a shipped agent's name or a run folder inside the studio's folder) on
        `level`, in the agent's own environment settings: every frame, how it ended and its return."""
        spec = self._valid(level)
        policy = self._policy(agent)
        size = spec.default_size()
        key = (policy.source, size)
        if key not in self._recorders:
            env, params = policy.env_for(size, "level")
            self._recorders[key] = (env, episode_recorder(env, params, policy.act, policy.config.env.max_steps))
        env, record = self._recorders[key]
        (episode,) = record([spec.build(env.static)], jax.random.key(_seed(seed))[None])
        frames = []
        for i in range(episode.length + 1):
            physics = jax.tree.map(lambda x, i=i: x[i], episode.physics)
            action = None if i == 0 else np.asarray(binding_values(episode.action_type, episode.actions[i - 1]))
            frames.append(scene_json(describe_scene(physics, episode.bindings, action)))
        rewards = np.concatenate([[0.0], np.cumsum(episode.rewards)])
        return {
            "frames": frames,
            "returns": [round(float(r), 4) for r in rewards],
            "ending": episode.ending,
            "return": episode.total_return,
            "step_seconds": episode.step_seconds,
        }

    def evaluate(self, level: Any, agent: Any, attempts: Any = 50, path: Any = None) -> dict:
        """The agent's solve rate on `level` over `attempts` sampled episodes (`kinetix eval`'s batched
        evaluator), and the `kinetix finetune` command for this level (`path`: where the level is saved)."""
        spec = self._valid(level)
        policy = self._policy(agent)
        if not isinstance(attempts, int) or isinstance(attempts, bool) or not 1 <= attempts <= MAX_ATTEMPTS:
            raise StudioError(400, f"attempts: expected a whole number in 1..{MAX_ATTEMPTS}, got {attempts!r}")
        with tempfile.TemporaryDirectory() as folder:
            file = Path(folder) / "level.json"
            file.write_text(json.dumps(level))
            try:
                (result,) = Evaluator(policy.config, [file], attempts)(policy.params)
            except UserError as exc:
                raise StudioError(422, str(exc).replace(str(file), "level")) from None
        # the command runs where the studio was started: paths relative to that folder
        target = os.path.relpath(self.workspace.path(path)) if isinstance(path, str) and path else "LEVEL.json"
        source = agent if agent in shipped_names() else os.path.relpath(self.workspace.path(agent))
        run = "runs/finetune-" + re.sub(r"[^a-z0-9]+", "-", spec.name.lower()).strip("-")
        return {
            "solve_rate": result.solve_rate,
            "mean_return": result.mean_return,
            "mean_length": result.mean_length,
            "attempts": attempts,
            "finetune": f"kinetix finetune {target} --from {source} --run-dir {run}",
        }

    def _policy(self, agent: Any) -> LoadedPolicy:
        if not isinstance(agent, str) or not agent:
            raise StudioError(400, f"agent: expected a shipped agent's name or a run folder, got {agent!r}")
        if agent not in shipped_names():
            self.workspace.path(agent)  # a run folder must lie inside the studio's folder
            agent = str(self.workspace.path(agent))
        if agent not in self._policies:
            try:
                self._policies[agent] = load_policy(agent)
            except UserError as exc:
                raise StudioError(422, str(exc)) from None
        return self._policies[agent]

    def _valid(self, level: Any) -> LevelSpec:
        try:
            spec = parse_level(level, "level")
            spec.default_size()
        except LevelError as exc:
            raise StudioError(422, f"{exc} (fix the level first)") from None
        return spec


def _unsolved(level: dict) -> dict:
    return {k: v for k, v in level.items() if k != "solution"}


def _body_slots(level: dict, size: str) -> list[int]:
    """The engine slot of each body in the file's order (polygons and circles are numbered apart)."""
    polygons, circles, slots = 0, 0, []
    for body in level.get("bodies", []):
        if body.get("shape") == "circle":
            slots.append(SIZES[size].num_polygons + circles)
            circles += 1
        else:
            slots.append(NUM_ARENA_POLYGONS + polygons)
            polygons += 1
    return slots


def _size(size: Any) -> str:
    if size not in SIZES:
        raise StudioError(400, f"size: expected one of {', '.join(SIZES)}, got {size!r}")
    return size


def _seed(seed: Any) -> int:
    if not isinstance(seed, int) or isinstance(seed, bool) or not 0 <= seed <= INT32_MAX:
        raise StudioError(400, f"seed: expected a whole number in 0..{INT32_MAX}, got {seed!r}")
    return seed


def _action(action: Any) -> np.ndarray:
    nvec = action_space("multi-discrete").nvec
    ok = isinstance(action, list) and len(action) == ACTION_WIDTH
    ok = ok and all(
        isinstance(v, int) and not isinstance(v, bool) and 0 <= v < n for v, n in zip(action, nvec, strict=True)
    )
    if not ok:
        raise StudioError(
            400, f"action: expected [m0, m1, m2, m3, t0, t1] with motors in 0..2, thrusters 0..1, got {action!r}"[:200]
        )
    return np.asarray(action, np.int32)


_FRESH: dict[str, Any] = {}
_MUTATORS: dict[tuple[str, int], Any] = {}


def _fresh(size: str):
    if size not in _FRESH:
        static, sampler = SIZES[size], default_config(size)
        _FRESH[size] = jax.jit(lambda key: jax.tree.map(lambda x: x[0], fresh_levels(static, sampler, key, 1)))
    return _FRESH[size]


def _mutator(size: str, edits: int):
    if (size, edits) not in _MUTATORS:
        _MUTATORS[size, edits] = jax.jit(lambda key, level: mutate_level(SIZES[size], key, level, edits))
    return _MUTATORS[size, edits]
