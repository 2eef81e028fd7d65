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
import shlex
import tempfile
import threading
from pathlib import Path
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from engine import SIZES, Scene
from kinetix_cli.constants import ACTION_WIDTH, INT32_MAX
from kinetix_cli.env.actions import action_space, binding_values
from kinetix_cli.env.environment import EnvState, KinetixEnv
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
from kinetix_cli.viz.scene import describe_scene, scene_json

MAX_EPISODES = 8
"""Episodes (played or watched) kept at once (the oldest is dropped)."""
MAX_ATTEMPTS = 1000
"""Attempts one evaluation request may ask for."""
MAX_EDITS = 64
"""Edits one mutation request may ask for."""
_ENTITY = re.compile(r"^(bodies|joints|thrusters)\[(\d+)\]")
_ENTITY_REF = re.compile(r"\b(bodies|joints|thrusters)\[(\d+)\]")


@dataclasses.dataclass
class _Episode:
    """An episode the page steps: played by the user's keys, or by an agent (`policy`, with its own key)."""

    spec: LevelSpec
    level: dict  # the level's JSON without its solution, as the episode started
    env: KinetixEnv
    stepper: tuple  # (env params, jitted step): see `_stepper`
    state: EnvState
    actions: list[list[int]]
    policy: LoadedPolicy | None = None
    key: jax.Array | None = None
    total_return: float = 0.0
    ending: str | None = None  # "solved", "failed", "timed out" once the episode is over


class Studio:
    """The studio's state: its folder, compiled functions, play sessions and loaded agents. One lock serialises
    the calls (the server runs requests on a thread pool; the studio has one user)."""

    def __init__(self, root: str | Path) -> None:
        self.workspace = Workspace(root)
        self.lock = threading.Lock()
        self._envs: dict[str, tuple] = {}
        self._agent_envs: dict[tuple[str, str], tuple] = {}
        self._episodes: collections.OrderedDict[str, _Episode] = collections.OrderedDict()
        self._policies: dict[str, LoadedPolicy] = {}

    # --- levels -----------------------------------------------------------------------------------------
    def check(self, level: Any) -> dict:
        """Whether `level` is a valid level, as `kinetix validate` says it: {"ok": true, "size", "scene",
        "slots"} (slots: each body's engine slot, to pick bodies on the page), or {"ok": false, "error", "entity",
        "field", "also"}: the parser's one line and, where it names one, the entity (e.g. "bodies[2]") and field;
        `also` lists the other entities whose field is at fault too (the earlier owner of a duplicate name)."""
        try:
            spec = parse_level(level, "level")
            size = spec.default_size()
            built = spec.build(SIZES[size])
        except LevelError as exc:
            message = str(exc).removeprefix("level: ")
            match = _ENTITY.match(message)
            field = message.split(": ")[1] if match and message.count(": ") >= 2 else None
            entity = match.group(0) if match else None
            others = [m.group(0) for m in _ENTITY_REF.finditer(message.partition(": ")[2])] if field == "name" else []
            return {"ok": False, "error": message, "entity": entity, "field": field, "also": others}
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

    # --- play and watch ---------------------------------------------------------------------------------
    def play_start(self, level: Any) -> dict:
        """Start an episode of `level` driven by the page's keys; returns its id and first frame."""
        spec = self._valid(level)
        env, params, step = self._env(spec.default_size())
        return self._start(_Episode(spec, _unsolved(level), env, (params, step), None, []))

    def watch_start(self, level: Any, agent: Any, seed: Any = 0) -> dict:
        """Start an episode of `level` played by `agent` (a shipped agent's name or a run folder inside the
        studio's folder) in its own environment settings, its actions sampled with `seed`; returns its id, first
        frame and the seconds one step stands for (the page steps it live at that pace)."""
        spec = self._valid(level)
        seed = _seed(seed)
        policy = self._policy(agent)
        size = spec.default_size()
        key = (policy.source, size)
        if key not in self._agent_envs:
            env, params = policy.env_for(size, "level")
            self._agent_envs[key] = (env, params, _stepper(env, policy))
            env, params, step = self._agent_envs[key]  # compile it now, not on the page's first step
            start = env.initial_state(spec.build(env.static))
            jax.block_until_ready(step(start, jax.random.key(0), params, policy.params))
        env, params, step = self._agent_envs[key]
        episode = _Episode(spec, _unsolved(level), env, (params, step), None, [], policy, jax.random.key(seed))
        return self._start(episode) | {"agent": agent}

    def play_step(self, play_id: Any, action: Any = None, steps: Any = 1) -> dict:
        """`steps` environment steps (1..8) of an episode; the frame after them. A played episode holds `action`
        (6 multi-discrete entries: motors 0 off, 1 forward, 2 backward; thrusters 0 off, 1 on); an agent's
        episode takes no action (its agent chooses). An ended episode stays ended."""
        episode = self._episode(play_id)
        if episode.policy is None:
            action = _action(action)
        elif action is not None:
            raise StudioError(400, "action: an agent's episode takes no action (its agent chooses)")
        if not isinstance(steps, int) or isinstance(steps, bool) or not 1 <= steps <= 8:
            raise StudioError(400, f"steps: expected a whole number in 1..8, got {steps!r}")
        params, step = episode.stepper
        reward, taken = 0.0, action
        for _ in range(steps):
            if episode.ending is not None:
                break
            if episode.policy is None:
                choice, network = jnp.asarray(action), None
            else:
                episode.key, choice = jax.random.split(episode.key)
                network = episode.policy.params
            episode.state, taken, r, done, solved, failed = step(episode.state, choice, params, network)
            episode.actions.append(np.asarray(taken).tolist())
            reward += float(r)
            if bool(done):
                episode.ending = "solved" if bool(solved) else "failed" if bool(failed) else "timed out"
        if taken is None:  # an ended agent's episode: the last action it took
            taken = episode.actions[-1] if episode.actions else None
        episode.total_return += reward
        return self._frame(episode, taken, reward)

    def play_solution(self, play_id: Any, level: Any) -> dict:
        """`level` with the played episode as its solution; only an episode that solved the level."""
        episode = self._episode(play_id)
        if episode.policy is not None:
            raise StudioError(409, "an agent's episode runs in its own settings; play the level to keep a solution")
        if episode.ending != "solved":
            raise StudioError(409, "the episode has not solved the level; only a solving episode can be kept")
        if not isinstance(level, dict) or _unsolved(level) != episode.level:
            raise StudioError(409, "the level changed since this episode started; play it again")
        return dict(level) | {"solution": encode_solution(np.asarray(episode.actions), len(episode.actions))}

    def _start(self, episode: _Episode) -> dict:
        play_id = secrets.token_hex(8)
        episode.state = episode.env.initial_state(episode.spec.build(episode.env.static))
        self._episodes[play_id] = episode
        while len(self._episodes) > MAX_EPISODES:
            self._episodes.popitem(last=False)
        return {"play": play_id, **self._frame(episode, None, 0.0)}

    def _frame(self, episode: _Episode, action: Any, reward: float) -> dict:
        physics = jax.tree.map(np.asarray, episode.state.physics)
        values = None if action is None else np.asarray(binding_values(episode.env.action, jnp.asarray(action)))
        scene = describe_scene(physics, episode.state.bindings, values)
        step_seconds = episode.env.frame_skip * float(episode.spec.engine_params().dt)
        return {
            "scene": scene_json(scene),
            "step": len(episode.actions),
            "reward": reward,
            "return": episode.total_return,
            "ending": episode.ending,
            "seconds": len(episode.actions) * step_seconds,
            "step_seconds": step_seconds,
        }

    def _episode(self, play_id: Any) -> _Episode:
        if not isinstance(play_id, str) or play_id not in self._episodes:
            raise StudioError(404, "play: no such episode (it ended long ago or the studio restarted); start again")
        return self._episodes[play_id]

    def _env(self, size: str) -> tuple:
        """(env, params, jitted step) at the solution settings for `size`, compiled on first use."""
        if size not in self._envs:
            env, params = make_env(SOLUTION_SETTINGS, SIZES[size])
            self._envs[size] = (env, params, _stepper(env))
        return self._envs[size]

    def warm(self, sizes: tuple[str, ...] = ("s", "m", "l")) -> None:
        """Compile the play step of each size now (a no-op step of an empty scene), so the first key press
        does not wait for it."""
        for size in sizes:
            env, params, step = self._env(size)
            level = LevelSpec("warm", "", size, Scene(), [], [], {}).build(SIZES[size])
            jax.block_until_ready(step(env.initial_state(level), jnp.zeros(ACTION_WIDTH, jnp.int32), params, None))

    # --- agents -----------------------------------------------------------------------------------------
    def agents(self) -> list[str]:
        return shipped_names()

    def evaluate(self, level: Any, agent: Any, attempts: Any = 50, path: Any = None) -> dict:
        """The agent's solve rate on `level` over `attempts` sampled episodes (`kinetix eval`'s batched
        evaluator), and the `kinetix finetune` command for this level (`path`: where the level is saved), quoted
        for a POSIX shell. Every argument is checked before the evaluation starts."""
        spec = self._valid(level)
        if not isinstance(attempts, int) or isinstance(attempts, bool) or not 1 <= attempts <= MAX_ATTEMPTS:
            raise StudioError(400, f"attempts: expected a whole number in 1..{MAX_ATTEMPTS}, got {attempts!r}")
        if path is not None and not isinstance(path, str):
            raise StudioError(400, f"path: expected the level file's path in the studio's folder, got {path!r}"[:200])
        # the command runs where the studio was started: paths relative to that folder
        target = _relative(self.workspace.path(path)) if path else "LEVEL.json"
        policy = self._policy(agent)
        source = agent if agent in shipped_names() else _relative(self.workspace.path(agent))
        run = "runs/finetune-" + (re.sub(r"[^a-z0-9]+", "-", spec.name.lower()).strip("-") or "level")
        with tempfile.TemporaryDirectory() as folder:
            file = Path(folder) / "level.json"
            file.write_text(json.dumps(level))
            try:
                (result,) = Evaluator(policy.config, [file], attempts)(policy.params)
            except UserError as exc:
                raise StudioError(422, str(exc).replace(str(file), "level")) from None
        return {
            "solve_rate": result.solve_rate,
            "mean_return": result.mean_return,
            "mean_length": result.mean_length,
            "attempts": attempts,
            "finetune": shlex.join(["kinetix", "finetune", target, "--from", source, "--run-dir", run]),
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


def _stepper(env: KinetixEnv, policy: LoadedPolicy | None = None):
    """One jitted environment step: `step(state, choice, env_params, network_params) -> (state, action, reward,
    done, solved, failed)`. Without a policy `choice` is the action; with one it is the key its sampling policy
    (`LoadedPolicy.acting`, the one every command plays agents with) draws the action with; `network_params` are
    an argument, not constants baked into the compile."""

    @jax.jit
    def step(state, choice, params, network_params):
        action = choice if policy is None else policy.acting(network_params)(choice, env.observe(state), state.steps)
        _, state, reward, terminated, truncated, info = env.step_env(state, action, params)
        return state, action, reward, terminated | truncated, info["solved"], info["failed"]

    return step


def _relative(path: Path) -> str:
    """`path` relative to the folder the studio was started in, never read as an option (`./-x.json`)."""
    relative = os.path.relpath(path)
    return f"./{relative}" if relative.startswith("-") else relative


def _unsolved(level: dict) -> dict:
    return {k: v for k, v in level.items() if k != "solution"}


def _body_slots(level: dict, size: str) -> list[int]:
    """The engine slot of each body in the file's order (polygons and circles are numbered apart)."""
    placed, slots = {"polygon": 0, "circle": 0}, []
    for body in level.get("bodies", []):
        kind = "circle" if body.get("shape") == "circle" else "polygon"
        slots.append(SIZES[size].slot(kind, placed[kind]))
        placed[kind] += 1
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
