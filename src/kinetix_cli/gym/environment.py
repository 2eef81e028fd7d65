"""Kinetix as a gymnax environment: `env, params = make(...)`, then gymnax's `reset(key, params)` and
`step(key, state, action, params)`.

`KinetixGymnax` is a `gymnax.environments.environment.Environment` over `KinetixEnv`: its step is `KinetixEnv.step`
(the same function training uses), and an ended episode restarts from a level drawn uniformly from the pool of
levels in `params` (`params.pool`). The pool is one of:

- a loaded pool: a suite (`"s"`, `"m"`, `"l"`), level files or folders of them, or a level set made by
  `kinetix generate`, padded to a power of two, so another pool of the same size and bucket runs without compiling
  again;
- fresh levels: a batch of new levels from the generator's distribution of the size (`FRESH_LEVELS` of them by
  default). `params = env.refresh_levels(key, params)` (jittable) draws the next batch of the same shape, in batches
  as `kinetix pretrain` does: a step never samples a level, so it costs what a step on a loaded pool costs.

`step` returns gymnax 1.x's `(obs, state, reward, terminated, truncated, info)`; `info` carries gymnax 1.x's
`terminated`, `truncated` and `discount` (0.0 where terminated, else 1.0), `final_observation` (the observation
before an auto-reset), and `solved`, `failed` (how an episode ended). The environment object is a frozen dataclass:
equal settings are one static argument to `jax.jit`, one compile.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Sequence
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
from flax import struct
from gymnax.environments import environment as gymnax_environment
from gymnax.environments import spaces

from engine import SIZES
from kinetix_cli.config import ConfigError, EnvSettings
from kinetix_cli.env.environment import EnvParams, EnvState, KinetixEnv
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import Level, index_level, level_count, stack_levels, to_device
from kinetix_cli.errors import UserError
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.levels.files import level_paths, load_level
from kinetix_cli.levels.levelset import MANIFEST_FILE, load_levelset

FRESH = "fresh"
"""The level source of newly generated levels."""

FRESH_LEVELS = {"s": 1024, "m": 1024, "l": 256}
"""Levels in a batch of fresh levels by size (`make`'s default `fresh_levels`). Sampling 1,024 levels took 0.1 s at
s and 0.2-0.5 s at m on a shared 2-core CPU (`kinetix bench gym`, BENCHMARKS.md); a level at l takes ~7 ms
(`kinetix_cli.generator.fresh.OVERSAMPLE`), so l draws 256 (~1.8 s). Episodes of random play last ~150 steps, so
64 environments start ~0.4 episodes a step: 1,024 levels last them ~2,400 steps."""


@struct.dataclass
class GymnaxParams(gymnax_environment.EnvParams):
    """Traced settings of `KinetixGymnax` (gymnax's `EnvParams` with Kinetix's own).

    Attributes:
        max_steps_in_episode: episode cap in environment steps (gymnax's name for `EnvParams.max_steps`).
        dense_reward_scale: weight of the green-blue distance shaping; 0 turns it off.
        pool: the levels resets draw from (leading axis): a loaded pool padded to a power of two, or a batch of
            fresh levels (`KinetixGymnax.refresh_levels` draws the next).
        pool_count: how many of `pool`'s rows are real levels (resets draw among the first `pool_count`).
    """

    max_steps_in_episode: int = EnvSettings.max_steps
    dense_reward_scale: float = EnvSettings.dense_reward_scale
    pool: Level | None = None
    pool_count: jax.Array | int = 0

    @property
    def env_params(self) -> EnvParams:
        return EnvParams(max_steps=self.max_steps_in_episode, dense_reward_scale=self.dense_reward_scale)


@dataclasses.dataclass(frozen=True, eq=True)
class KinetixGymnax(gymnax_environment.Environment[EnvState, GymnaxParams]):
    """The gymnax environment of one `KinetixEnv` (size, observation, action, frame skip) and level source.

    Attributes:
        env: the Kinetix environment every step runs.
        fresh: the level sampler `refresh_levels` draws batches with when the source is fresh levels, else None.
        defaults: the `GymnaxParams` of `default_params` (the pool `make` loaded); not part of equality.
    """

    env: KinetixEnv
    fresh: FreshLevels | None = None
    defaults: GymnaxParams = dataclasses.field(default_factory=GymnaxParams, compare=False, repr=False)

    @property
    def name(self) -> str:
        return f"Kinetix-{_size_name(self.env)}"

    @property
    def default_params(self) -> GymnaxParams:
        return self.defaults

    @property
    def num_actions(self) -> int:
        """What gymnax's `num_actions` counts here, by action type:

        - discrete: the choices (11), as `action_space(params).n`: what a categorical policy head needs;
        - multi-discrete: the entries (6: 4 motors, 2 thrusters), not the choices; entry i has
          `action_space(params).nvec[i]` choices (3 per motor, 2 per thruster: 324 combinations);
        - continuous: the entries (6), as `action_space(params).shape[0]`.
        """
        space = self.env.action_space
        return int(space.nvec[0] if space.kind == "discrete" else space.shape[0])

    def reset_level(self, key: jax.Array, params: GymnaxParams) -> Level:
        """The level an episode (re)starts from: one of the pool's first `pool_count` levels, uniformly."""
        if params.pool is None:
            raise ValueError("these params carry no level pool: make them with kinetix_cli.gym.make")
        return index_level(params.pool, jax.random.randint(key, (), 0, params.pool_count))

    def refresh_levels(self, key: jax.Array, params: GymnaxParams) -> GymnaxParams:
        """`params` with a new batch of fresh levels, drawn with `key`, in place of its pool.

        The batch has the pool's count and shapes, so nothing that takes `params` compiles again; jittable (call it
        inside your jitted update, or between scans). Call it in batches, as `kinetix pretrain` does: e.g. once as
        many episodes have started as the pool holds, or each update with a pool of `num_envs` levels. With a
        loaded pool (no sampler), `params` comes back unchanged.
        """
        if self.fresh is None:
            return params
        count = level_count(params.pool)
        return params.replace(pool=_fresh_batch(self.fresh, key, count), pool_count=jnp.int32(count))

    def reset_env(self, key: jax.Array, params: GymnaxParams):
        return self.env.reset_to_level(self.reset_level(key, params))

    def step(self, key: jax.Array, state: EnvState, action, params: GymnaxParams | None = None):
        """One step of `KinetixEnv.step`; an ended episode restarts from a pool level drawn with `key`.

        Returns (obs, state, reward, terminated, truncated, info); info: `terminated`, `truncated`, `discount`
        (() float32, 0 where terminated), `final_observation`, `solved`, `failed`, `distance`, `dropped_contacts`.
        """
        params = self.default_params if params is None else params
        return _step(self, key, state, action, params)

    def reset(self, key: jax.Array, params: GymnaxParams | None = None):
        params = self.default_params if params is None else params
        return _reset(self, key, params)

    def step_env(self, key: jax.Array, state: EnvState, action, params: GymnaxParams):
        """gymnax's step without reset: (obs, state, reward, terminated, info); `is_truncated` gives the rest."""
        obs, state, reward, terminated, _, info = self.env.step_env(state, action, params.env_params)
        return obs, state, reward, terminated, info

    def get_obs(self, state: EnvState, params=None, key=None):
        return self.env.observe(state)

    def is_truncated(self, state: EnvState, params: GymnaxParams) -> jax.Array:
        return state.steps >= params.max_steps_in_episode

    def is_terminated(self, state: EnvState, params: GymnaxParams) -> jax.Array:
        raise NotImplementedError("a Kinetix episode's termination is known only from its step (contacts)")

    def action_space(self, params: GymnaxParams | None = None) -> spaces.Space:
        space = self.env.action_space
        if space.kind == "discrete":
            return spaces.Discrete(space.nvec[0])
        if space.kind == "multi-discrete":
            return MultiDiscrete(space.nvec)
        return spaces.Box(jnp.asarray(space.low), jnp.asarray(space.high), space.shape, jnp.float32)

    def observation_space(self, params: GymnaxParams | None = None) -> spaces.Space:
        """A Box (flat vector; pixels in [0, 1]) or, for entity observations, a Dict of Boxes by field."""
        shapes = jax.eval_shape(lambda: self.env.reset_to_level(jax.tree.map(jnp.asarray, _empty(self.env)))[0])
        if self.env.observation == "pixels":
            return spaces.Box(0.0, 1.0, shapes.shape, jnp.float32)
        if self.env.observation == "symbolic-flat":
            return spaces.Box(-jnp.inf, jnp.inf, shapes.shape, jnp.float32)
        return spaces.Dict({field: _box(leaf) for field, leaf in _fields(shapes)})


class MultiDiscrete(spaces.Box):
    """Independent choices per entry: entry i takes a value in 0..nvec[i] - 1.

    gymnax has no such space: this is a gymnax `Box` of int32 from 0 to `nvec - 1` (so gymnax's converters, e.g.
    `GymnaxToGymWrapper`, take it, as a Gymnasium `Box` of integers) that samples each entry uniformly.
    """

    def __init__(self, nvec: Sequence[int]):
        self.nvec = tuple(int(n) for n in nvec)
        high = np.asarray(self.nvec, np.int32) - 1
        super().__init__(np.zeros_like(high), high, (len(self.nvec),), jnp.int32)

    def __repr__(self) -> str:
        return f"MultiDiscrete({list(self.nvec)})"

    def sample(self, key: jax.Array) -> jax.Array:
        return jax.random.randint(key, self.shape, 0, jnp.asarray(self.nvec), jnp.int32)


@functools.partial(jax.jit, static_argnums=0)
def _step(env: KinetixGymnax, key, state, action, params):
    level = env.reset_level(key, params)
    obs, state, reward, terminated, truncated, info = env.env.step(state, action, params.env_params, level)
    discount = 1.0 - terminated.astype(jnp.float32)
    info = info | {"terminated": terminated, "truncated": truncated, "discount": discount}
    return obs, state, reward, terminated, truncated, info


@functools.partial(jax.jit, static_argnums=0)
def _reset(env: KinetixGymnax, key, params):
    return env.reset_env(key, params)


@functools.partial(jax.jit, static_argnums=(0, 2))
def _fresh_batch(fresh: FreshLevels, key: jax.Array, count: int) -> Level:
    return fresh(key, count)


def make(
    levels: str | Path | Sequence[str | Path] = FRESH,
    size: str | None = None,
    observation: str = "symbolic-flat",
    action: str = "multi-discrete",
    *,
    frame_skip: int = EnvSettings.frame_skip,
    max_steps: int = EnvSettings.max_steps,
    dense_reward_scale: float = EnvSettings.dense_reward_scale,
    fresh_levels: int | None = None,
) -> tuple[KinetixGymnax, GymnaxParams]:
    """A Kinetix gymnax environment and its default params, in one call.

    Args:
        levels: the level source: `"fresh"` (batches of newly generated levels of `size`; the first is drawn
            with `jax.random.key(0)`, `env.refresh_levels` draws the next), a shipped suite (`"s"`, `"m"`, `"l"`),
            a level file, a folder of them, a level set (a folder made by `kinetix generate`), or a list of files
            and folders.
        size: the size every level is built at ('s', 'm', 'l'); default: the largest the pool's levels need, or
            'm' for fresh levels. A level too big for it is an error.
        observation: 'symbolic-flat' (one float32 vector; default), 'symbolic-entity' (per-entity rows and
            masks, a pytree) or 'pixels' (125 x 125 x 3 in [0, 1]).
        action: 'multi-discrete' (6 entries: 4 motors in {off, +1, -1}, 2 thrusters in {off, on}), 'discrete'
            (11 choices) or 'continuous' (6 values).
        frame_skip: engine steps per environment step (as in an experiment's `env` section).
        max_steps: episode cap [environment steps].
        dense_reward_scale: weight of the green-blue distance shaping; 0 turns it off.
        fresh_levels: levels in a batch of fresh levels (`levels="fresh"` only); default `FRESH_LEVELS[size]`.

    Raises:
        UserError: a bad setting, a missing or invalid level file, a level too big for `size`.
    """
    try:  # the experiment config's checks and messages: one way from settings to an environment (`make_env`)
        settings = EnvSettings(
            size=size or "m",
            observation=observation,
            action=action,
            frame_skip=frame_skip,
            max_steps=max_steps,
            dense_reward_scale=dense_reward_scale,
        )
    except ConfigError as exc:
        raise UserError(str(exc).removeprefix("env.")) from None
    if isinstance(levels, str) and levels == FRESH:
        count = FRESH_LEVELS[settings.size] if fresh_levels is None else fresh_levels
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise UserError(f"fresh_levels: expected a whole number >= 1, got {fresh_levels!r}")
        env, params = _make(settings)
        fresh = FreshLevels.for_size(env.static, settings.size)
        params = params.replace(pool=_fresh_batch(fresh, jax.random.key(0), count), pool_count=jnp.int32(count))
        return KinetixGymnax(env, fresh, params), params
    if fresh_levels is not None:
        raise UserError(f"fresh_levels: only for levels='fresh'; {levels!r} is a pool of its own levels")
    pool, settings = _pool(levels, settings, size is not None)
    env, params = _make(settings)
    params = params.replace(pool=to_device(_pad(pool)), pool_count=jnp.int32(level_count(pool)))
    return KinetixGymnax(env, None, params), params


def _make(settings: EnvSettings) -> tuple[KinetixEnv, GymnaxParams]:
    """`make_env`'s environment for `settings`, and its parameters as gymnax's params (no levels yet)."""
    env, env_params = make_env(settings)
    return env, GymnaxParams(
        max_steps_in_episode=env_params.max_steps, dense_reward_scale=env_params.dense_reward_scale
    )


def _pool(levels, settings: EnvSettings, size_given: bool) -> tuple[Level, EnvSettings]:
    """The levels of a pool source as one batch, and the settings at the size they are built at (with no size
    given: the largest the levels need)."""
    sources = [levels] if isinstance(levels, str | Path) else list(levels)
    if not sources:
        raise UserError("levels: an empty list; name a suite, level files or folders, or 'fresh'")
    if len(sources) == 1 and (Path(sources[0]) / MANIFEST_FILE).is_file():
        levelset = load_levelset(sources[0])
        made = levelset.manifest["size"]
        if size_given and settings.size != made:
            raise UserError(f"{sources[0]}: a level set of size {made}; size={settings.size!r} asks for another")
        return levelset.levels, dataclasses.replace(settings, size=made)
    specs = [load_level(path) for path in level_paths(sources)]
    if not size_given:
        needed = max((spec.default_size() for spec in specs), key=list(SIZES).index)
        settings = dataclasses.replace(settings, size=needed)
    return stack_levels([spec.build(SIZES[settings.size]) for spec in specs]), settings


def _pad(pool: Level) -> Level:
    """`pool` with its first level repeated up to the next power of two (resets never draw the copies)."""
    count = level_count(pool)
    rows = np.arange(1 << max(count - 1, 0).bit_length())
    rows = np.where(rows < count, rows, 0)
    return jax.tree.map(lambda x: np.asarray(x)[rows], pool)


def _size_name(env: KinetixEnv) -> str:
    return next(name for name, static in SIZES.items() if static == env.static)


def _empty(env: KinetixEnv) -> Level:
    return jax.tree.map(lambda x: x[0], FreshLevels.for_size(env.static, _size_name(env)).placeholder())


def _fields(tree) -> list[tuple[str, jax.ShapeDtypeStruct]]:
    return [(field.name, getattr(tree, field.name)) for field in dataclasses.fields(tree)]


def _box(leaf: jax.ShapeDtypeStruct) -> spaces.Box:
    if leaf.dtype == jnp.bool_:
        return spaces.Box(0, 1, leaf.shape, jnp.bool_)
    if jnp.issubdtype(leaf.dtype, jnp.integer):
        return spaces.Box(-1, np.iinfo(np.int32).max, leaf.shape, leaf.dtype)
    return spaces.Box(-jnp.inf, jnp.inf, leaf.shape, leaf.dtype)
