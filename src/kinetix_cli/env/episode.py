"""One episode runner for every caller: policy evaluation, GIF recordings, the solver, solution replays and the
generator's filters.

`run_episode(env, params, level, policy, key, horizon)` plays one episode from `level` (no auto-reset) and
returns its `Outcome`; with `record=True` also a `Trace` of every step; with `restart=True` it plays all `horizon`
steps, an episode that ends restarting from `level` (SFL's scoring counts the episodes solved). A policy is a pure
function
`policy(key, obs, t) -> action`: `open_loop(actions)` replays a fixed (horizon, ...) action sequence (the
observation is never computed then), `kinetix_cli.rl.networks.sampling_policy` samples from a network. The
episode's key is split into one key per step, handed to the policy. Steps after the episode ended are computed
(a scan has a fixed length) but not counted.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import jax
import jax.numpy as jnp
import numpy as np
from flax import struct

from engine import State
from kinetix_cli.env.environment import EnvParams, EnvState, KinetixEnv
from kinetix_cli.env.level import Level, share_engine_params
from kinetix_cli.trace_cache import cached_jit

Policy = Callable[[jax.Array, object, jax.Array], jax.Array]
"""policy(key, observation, t) -> action, for one environment; t is the () int32 step index."""


@struct.dataclass
class Outcome:
    """How one episode went (shapes () per episode, a leading axis in batches).

    Attributes:
        solved: the episode ended with green touching blue.
        failed: it ended with green touching red.
        length: environment steps until the end (the horizon if it never ended).
        total_return: summed reward, shaping included.
        min_distance: smallest green-blue distance seen [m].
        episodes: episodes that ended (0 or 1; with `run_episode`'s `restart`, every one in the horizon).
        solves: those of them that ended solved.

    With `restart` the first five are over every episode played: any solved, any failed, the steps played, the
    summed return and the smallest distance.
    """

    solved: jax.Array
    failed: jax.Array
    length: jax.Array
    total_return: jax.Array
    min_distance: jax.Array
    episodes: jax.Array
    solves: jax.Array

    @staticmethod
    def start(state: EnvState) -> Outcome:
        """Nothing happened yet."""
        nothing, zero = jnp.bool_(False), jnp.int32(0)
        return Outcome(nothing, nothing, zero, jnp.float32(0.0), state.distance, zero, zero)

    def after_step(self, done: jax.Array, reward: jax.Array, ended: jax.Array, info: dict) -> Outcome:
        """Count one environment step unless the episode had already ended (`done` before the step); `ended`: the
        step ended an episode."""
        live = ~done
        return Outcome(
            solved=self.solved | (live & info["solved"]),
            failed=self.failed | (live & info["failed"]),
            length=self.length + live.astype(jnp.int32),
            total_return=self.total_return + jnp.where(live, reward, 0.0),
            min_distance=jnp.where(live, jnp.minimum(self.min_distance, info["distance"]), self.min_distance),
            episodes=self.episodes + (live & ended).astype(jnp.int32),
            solves=self.solves + (live & ended & info["solved"]).astype(jnp.int32),
        )


@struct.dataclass
class Trace:
    """Every step of a recorded episode (leading axis = step; entries after the end are not part of it).

    Attributes:
        physics: engine `State` after each step.
        action: the action taken at each step.
        reward: (H,) rewards.
        done: (H,) bool, the episode ended at this step.
    """

    physics: State
    action: jax.Array
    reward: jax.Array
    done: jax.Array


def open_loop(actions: jax.Array) -> Policy:
    """The policy that takes `actions[t]` at step t, whatever it observes."""
    actions = jnp.asarray(actions)
    return lambda key, obs, t: actions[t]


def run_episode(
    env: KinetixEnv,
    params: EnvParams,
    level: Level,
    policy: Policy,
    key: jax.Array,
    horizon: int,
    record: bool = False,
    restart: bool = False,
) -> Outcome | tuple[Outcome, Trace]:
    """Play one episode of at most `horizon` steps from `level`, or with `restart` (static) `horizon` steps in
    which every episode that ends restarts from `level`. Pure; vmap over levels, keys or policies' data.

    Returns the `Outcome`, and with `record` (static) also the `Trace` of every step.
    """
    state = env.initial_state(level)

    def body(carry, inputs):
        state, outcome, done = carry
        t, k = inputs
        action = policy(k, env.observe(state), t)
        if restart:
            _, state, reward, terminated, truncated, info = env.step(state, action, params, level)
        else:
            _, state, reward, terminated, truncated, info = env.step_env(state, action, params)
        ended = terminated | truncated
        trace = Trace(state.physics, action, reward, ~done & ended) if record else None
        outcome = outcome.after_step(done, reward, ended, info)
        return (state, outcome, done if restart else done | ended), trace

    steps = (jnp.arange(horizon, dtype=jnp.int32), jax.random.split(key, horizon))
    (_, outcome, _), trace = jax.lax.scan(body, (state, Outcome.start(state), jnp.bool_(False)), steps)
    return (outcome, trace) if record else outcome


@cached_jit(static_argnums=(0, 4))
def _replay(env: KinetixEnv, params: EnvParams, levels: Level, actions: jax.Array, level_axes) -> Outcome:
    episode = functools.partial(run_episode, env, params, key=jax.random.key(0), horizon=actions.shape[1])
    return jax.vmap(lambda level, seq: episode(level, open_loop(seq)), in_axes=(level_axes, 0))(levels, actions)


def replay(env: KinetixEnv, params: EnvParams, levels: Level, actions) -> Outcome:
    """Open-loop episodes: levels (B, ...) with action sequences (B, H, ...), the horizon H; host results.

    The batch is padded to the next power of two (copies of its first row, dropped from the result), so that
    callers with nearby batch sizes share one compile per environment, horizon and bucket; engine constants the
    levels share are passed once (`share_engine_params`)."""
    count = np.shape(actions)[0]
    padded = 1 << max(count - 1, 0).bit_length()
    rows = np.where(np.arange(padded) < count, np.arange(padded), 0)

    def pad(x):  # on the host: no compile per leaf shape
        return np.asarray(x)[rows]

    levels, level_axes = share_engine_params(jax.tree.map(pad, levels))
    outcome = _replay(env, params, levels, pad(np.asarray(actions)), level_axes)
    return jax.tree.map(lambda x: np.asarray(x)[:count], outcome)
