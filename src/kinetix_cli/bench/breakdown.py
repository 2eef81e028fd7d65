"""Where one PPO update's time goes (`kinetix bench train --breakdown`), measured beside the whole update.

For one model and environment count, at exactly the update's shapes (`UpdateSetup`):

- the environment alone (`bench.env.bench_env`: random actions, auto-reset, the same observation type, envs and
  steps per call), the ceiling of the update's env steps/s. It skips what only a rollout reads (the final
  observation before a reset), so the `env step` phase below may take longer;
- each phase of `ppo.ppo_update` compiled as a function of its own and timed as the median over repeated calls
  (`bench.timing.time_calls`) on the transitions of one real rollout, in ms per update and as a share of the
  whole update's median:
  `env step` (the rollout's `num_steps` vmapped `env.step` calls, actions given, ended episodes restarting from
  pool levels, the final observation read as the rollout reads it), `rollout forward` (the rollout's network
  passes as `ppo.collect` makes them: one on each step's observations with action sampling, and
  `ppo.final_values` on the final observations of the rollout's truncated episodes), `GAE` (`ppo.gae`), `learn`
  (`ppo.learn`: the epochs' forward, backward and Adam steps) and `host sync` (the `jax.device_get` of the
  update's metrics dict, as `rl.record` does it). Inside one jitted update XLA fuses and overlaps the phases, and
  the rollout's stacking of transitions belongs to no phase, so the phases need not sum to the whole:
  `phase_sum_ms` stands beside `update_ms`;
- FLOPs from XLA's own cost analysis of each compiled phase. XLA's cost analysis may count a loop's body once,
  whatever its trip count (this version's CPU backend does, at every nesting level); a probe (`loops_counted`)
  finds out, and each phase's figure is scaled by its own loops' trip counts (num_steps, or epochs x
  minibatches) where XLA did not. Loops inside `env.step` (frame skip, solver iterations) are not scaled: the
  env step's FLOPs are a lower bound. `xla_update_gflop` is XLA's figure for the whole compiled update as it
  reports it;
- the machine's matmul limit in this process: float32 and bfloat16 matmuls at the update's dominant shapes
  (`matmul_shapes`), in GFLOP/s; the update's achieved FLOP/s as a share of the float32 limit;
- the curriculum's scoring, given SFL settings (`scoring_time`): one refresh of its buffer
  (`rl.curricula.sfl.refresh_buffer`: `score_levels` levels x `score_attempts` copies x `score_steps` steps,
  drawn from the pool) with the update's network, timed as the median over repeated calls, and what a run pays
  for it per update (one refresh every `refresh_every` updates) and as a share of the run's time. The candidates
  are the pool's full random levels; a run that scores fresh levels also pays for generating them.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import statistics
import time
from collections.abc import Callable
from typing import Any

import flax.linen as nn
import jax
import jax.numpy as jnp

from kinetix_cli.bench.env import EnvBenchConfig, bench_env
from kinetix_cli.bench.timing import time_calls
from kinetix_cli.config import CurriculumSettings, ExperimentConfig
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.level import Level, draw_levels
from kinetix_cli.parallel import batch_sharded
from kinetix_cli.rl.buffer import empty_buffer
from kinetix_cli.rl.curricula.sfl import refresh_buffer
from kinetix_cli.rl.ppo import Runner, Transition, collect, final_values, gae, learn, rollout_metrics, truncated_rows

PHASES = ("env step", "rollout forward", "GAE", "learn", "host sync")
"""The phases of one update, in the order it runs them."""
SYNC_REPEATS = 21
"""Host syncs timed (each of freshly computed metrics) for the median."""
MATMUL_TIME = 1.0
"""Longest timing of one matmul shape and dtype [s] (the benchmark's `min_time` when shorter)."""
MATMUL_CALL_S = 0.01
"""Shortest time of one timed matmul call [s]: each call loops over enough products to last it, so the call's
dispatch does not count."""
MATMUL_OPERANDS = 4
"""Distinct left operands the products of a matmul call cycle through (so XLA cannot hoist the product)."""


@dataclasses.dataclass(frozen=True)
class UpdateSetup:
    """What one measured update is built from: `ppo_update(runner, env_params, pool, env=, network=,
    settings=experiment.ppo)`."""

    experiment: ExperimentConfig
    env: KinetixEnv
    env_params: EnvParams
    network: nn.Module
    pool: Level


@dataclasses.dataclass
class PhaseTime:
    """One phase of the update compiled alone.

    Attributes:
        name: one of `PHASES`.
        ms: median time of the phase per update [ms].
        share: `ms` / the whole update's median time [fraction].
        gflop: its FLOPs per update (XLA's cost analysis, loops scaled) [GFLOP]; 0 for host sync.
    """

    name: str
    ms: float
    share: float
    gflop: float


@dataclasses.dataclass
class MatmulRate:
    """One jitted matmul (rows, inner) @ (inner, cols) timed alone.

    Attributes:
        shape: (rows, inner, cols).
        dtype: 'float32' or 'bfloat16'.
        gflop_per_s: 2 x rows x inner x cols per product over the median seconds per product [GFLOP/s].
    """

    shape: tuple[int, int, int]
    dtype: str
    gflop_per_s: float


@dataclasses.dataclass
class ScoringTime:
    """SFL's scoring as a run with its settings pays it (`scoring_time`).

    Attributes:
        levels: levels scored per refresh (`curriculum.score_levels`).
        attempts: copies of each level played (`curriculum.score_attempts`).
        steps: steps each copy plays (`curriculum.score_steps`).
        refresh_every: updates per refresh (`curriculum.refresh_every`).
        refresh_ms: median time of one refresh [ms].
        steps_per_s: the refresh's levels x attempts x steps env steps per second [env steps/s].
        per_update_ms: `refresh_ms` / `refresh_every`: the scoring's time per update of a run [ms].
        share: `per_update_ms` / (the update's time + `per_update_ms`): the scoring's share of a run's time
            [fraction].
    """

    levels: int
    attempts: int
    steps: int
    refresh_every: int
    refresh_ms: float
    steps_per_s: float
    per_update_ms: float
    share: float


@dataclasses.dataclass
class Breakdown:
    """Where one update's time goes, its FLOPs and the machine's matmul limit (see the module docstring).

    Attributes:
        update_ms: median time of the whole jitted update [ms].
        env_only_steps_per_s: the environment alone at the same envs and observation [env steps/s].
        env_only_ms: the environment alone's time for the update's envs x num_steps steps [ms].
        final_value_rows: rows of the rollout's second pass per step, on the truncated episodes' final
            observations when at most that many were truncated (`ppo.truncated_rows`; else a pass on all).
        phases: the phases in `PHASES` order.
        phase_sum_ms: the phases' times summed [ms] (fusion: not the update's time).
        update_gflop: the phases' FLOPs summed [GFLOP per update].
        update_gflop_per_s: `update_gflop` / the update's seconds [GFLOP/s].
        learn_gflop: the learn phase's FLOPs [GFLOP per update].
        learn_gflop_per_s: `learn_gflop` / the learn phase's seconds [GFLOP/s].
        xla_update_gflop: XLA's cost analysis of the whole compiled update as it reports it [GFLOP].
        loops_counted: whether XLA's cost analysis multiplies loop bodies by their trip counts.
        matmuls: the matmul limit at each dominant shape and dtype.
        f32_limit_gflop_per_s: the best float32 matmul rate [GFLOP/s].
        best_limit_gflop_per_s: the best matmul rate of any dtype [GFLOP/s].
        f32_limit_share: `update_gflop_per_s` / `f32_limit_gflop_per_s` [fraction].
        scoring: SFL's scoring beside the update (None: not asked for).
    """

    update_ms: float
    env_only_steps_per_s: float
    env_only_ms: float
    final_value_rows: int
    phases: list[PhaseTime]
    phase_sum_ms: float
    update_gflop: float
    update_gflop_per_s: float
    learn_gflop: float
    learn_gflop_per_s: float
    xla_update_gflop: float
    loops_counted: bool
    matmuls: list[MatmulRate]
    f32_limit_gflop_per_s: float
    best_limit_gflop_per_s: float
    f32_limit_share: float
    scoring: ScoringTime | None = None


def measure_breakdown(
    setup: UpdateSetup,
    runner: Runner,
    update: Callable,
    update_ms: float,
    min_time: float,
    seed: int,
    levels: int,
    scoring: CurriculumSettings | None = None,
) -> Breakdown:
    """The breakdown of one update. `update(runner) -> (runner,)` is the function whose median time was
    `update_ms` (its compile is cached, so costing it compiles nothing); `min_time` is the seconds each phase is
    timed for; `seed` and `levels` are the level pool's, for the environment-only ceiling; `scoring`, SFL's
    settings whose scoring is timed beside the update (None: none)."""
    counted = loops_counted()
    xla_update = xla_flops(jax.jit(update).lower(runner).compile())  # cached when the update was timed
    phases = time_phases(setup, runner, update_ms, counted, min_time)
    update_gflop = sum(p.gflop for p in phases)
    learn = phases[PHASES.index("learn")]
    matmuls = matmul_limits(matmul_shapes(setup, runner.obs), min(min_time, MATMUL_TIME))
    f32 = max(m.gflop_per_s for m in matmuls if m.dtype == "float32")
    achieved = update_gflop / (update_ms / 1e3)
    env_only = env_only_rate(setup, min_time, seed, levels)
    return Breakdown(
        update_ms=update_ms,
        env_only_steps_per_s=env_only,
        env_only_ms=1e3 * setup.experiment.ppo.batch_size / env_only,
        final_value_rows=truncated_rows(setup.experiment.ppo.num_envs),
        phases=phases,
        phase_sum_ms=sum(p.ms for p in phases),
        update_gflop=update_gflop,
        update_gflop_per_s=achieved,
        learn_gflop=learn.gflop,
        learn_gflop_per_s=learn.gflop / (learn.ms / 1e3),
        xla_update_gflop=xla_update / 1e9,
        loops_counted=counted,
        matmuls=matmuls,
        f32_limit_gflop_per_s=f32,
        best_limit_gflop_per_s=max(m.gflop_per_s for m in matmuls),
        f32_limit_share=achieved / f32,
        scoring=None if scoring is None else scoring_time(setup, runner, scoring, update_ms, min_time),
    )


def time_phases(
    setup: UpdateSetup, runner: Runner, update_ms: float, counted: bool, min_time: float
) -> list[PhaseTime]:
    """Every phase in `PHASES` compiled alone and timed on one rollout of `runner` (its transitions, advantages
    and targets). `counted`: whether XLA's cost analysis multiplies
    loop bodies by their trip counts (`loops_counted`)."""
    settings = setup.experiment.ppo
    runner, transitions, finished = jax.jit(_rollout(setup))(runner)
    advantages, targets = jax.jit(gae, static_argnums=(1, 2))(transitions, settings.gamma, settings.gae_lambda)
    losses = _zero_losses(setup, runner, transitions, advantages, targets)
    steps, passes = settings.num_steps, settings.update_epochs * settings.num_minibatches
    phase_runs = [  # (phase, its carry, trip count of its loops)
        (env_phase(setup), (runner.env_state, runner.obs, runner.key, _zero(), transitions.action), steps),
        (forward_phase(setup.network), (runner.params, transitions, runner.key, _zero()), steps),
        (gae_phase(settings.gamma, settings.gae_lambda), (transitions, advantages, targets), steps),
        (learn_phase(setup), (runner, transitions, advantages, targets, losses), passes),
    ]
    timed = [_phase(fn, carry, trips, counted, min_time) for fn, carry, trips in phase_runs]
    timed.append((host_sync_ms(transitions, finished, losses), 0.0))
    phases = [PhaseTime(name, ms, ms / update_ms, flop / 1e9) for name, (ms, flop) in zip(PHASES, timed, strict=True)]
    return phases


def scoring_time(
    setup: UpdateSetup, runner: Runner, curriculum: CurriculumSettings, update_ms: float, min_time: float
) -> ScoringTime:
    """One SFL refresh with `curriculum`'s settings (`scoring_phase`) timed for `min_time` seconds with the
    runner's parameters, and what a run pays for it beside updates of `update_ms`."""
    steps = curriculum.score_levels * curriculum.score_attempts * curriculum.score_steps
    buffer = empty_buffer(setup.pool, curriculum.buffer_size)
    _, rate, _ = time_calls(scoring_phase(setup, curriculum), (runner.params, runner.key, buffer), steps, min_time)
    refresh_ms = 1e3 * steps / rate
    per_update = refresh_ms / curriculum.refresh_every
    return ScoringTime(
        levels=curriculum.score_levels,
        attempts=curriculum.score_attempts,
        steps=curriculum.score_steps,
        refresh_every=curriculum.refresh_every,
        refresh_ms=refresh_ms,
        steps_per_s=rate,
        per_update_ms=per_update,
        share=per_update / (update_ms + per_update),
    )


def trace_updates(update: Callable, runner: Runner, directory: str, count: int) -> None:
    """Write a JAX profiler trace of `count` calls of `update(runner) -> (runner,)` into `directory`
    (TensorBoard's profile plugin and Perfetto read it: `plugins/profile/<time>/`); each call is one step."""
    compiled = jax.jit(update).lower(runner).compile()  # cached when the update was timed: nothing compiles here
    carry = (runner,)
    with jax.profiler.trace(directory, create_perfetto_trace=True):
        for number in range(count):
            with jax.profiler.StepTraceAnnotation("ppo_update", step_num=number):
                carry = jax.block_until_ready(compiled(*carry))


# --- the phases, each `carry -> carry` at the update's shapes (the carry keeps every result live) -------------


def env_phase(setup: UpdateSetup) -> Callable:
    """(env_state, obs, key, checksum, actions) -> the same after the rollout's `num_steps` environment steps
    with the given (num_steps, envs, ...) actions; restarts are drawn from the pool per step as `ppo.collect`
    draws them, and the final observation, rewards and flags fold into the scalar `checksum`."""
    env, params, pool, envs = setup.env, setup.env_params, setup.pool, setup.experiment.ppo.num_envs
    step = jax.vmap(env.step, in_axes=(0, 0, None, 0))

    def run(env_state, obs, key, checksum, actions):
        def body(carry, action):
            env_state, _, key, checksum = carry
            key, k_reset = jax.random.split(key)
            restart = batch_sharded(draw_levels(pool, k_reset, envs))
            obs, env_state, reward, terminated, truncated, info = step(env_state, action, params, restart)
            checksum = checksum + _total((reward, terminated, truncated, info["solved"], info["final_observation"]))
            return (env_state, obs, key, checksum), None

        (env_state, obs, key, checksum), _ = jax.lax.scan(body, (env_state, obs, key, checksum), actions)
        return env_state, obs, key, checksum, actions

    return run


def forward_phase(network: nn.Module) -> Callable:
    """(params, transitions, key, checksum) -> the same after the rollout's network passes on the (num_steps,
    envs, ...) transitions of a real rollout, as `ppo.collect` makes them: per step, one on the step's
    observations (sampling an action and its log-probability) and `ppo.final_values` on the next step's
    observations in place of the final ones, for the step's truncated episodes."""

    def run(params, transitions: Transition, key, checksum):
        steps = transitions.done.shape[0]

        def body(carry, t):
            key, checksum = carry
            key, k_act = jax.random.split(key)
            at = lambda i: jax.tree.map(lambda x: x[(t + i) % steps], transitions)  # noqa: E731
            dist, value = network.apply(params, at(0).obs)
            truncated = (at(0).done > 0) & (at(0).terminated == 0)
            final = final_values(network, params, at(1).obs, truncated)
            total = dist.log_prob(dist.sample(k_act)).sum() + value.sum() + final.sum()
            return (key, checksum + total), None

        (key, checksum), _ = jax.lax.scan(body, (key, checksum), jnp.arange(steps))
        return params, transitions, key, checksum

    return run


def gae_phase(gamma: float, gae_lambda: float) -> Callable:
    """(transitions, advantages, targets) -> (transitions, new advantages, new targets): `ppo.gae`."""

    def run(transitions: Transition, advantages, targets):
        return transitions, *gae(transitions, gamma, gae_lambda)

    return run


def learn_phase(setup: UpdateSetup) -> Callable:
    """(runner, transitions, advantages, targets, losses) -> (runner with new parameters, optimiser state and key,
    the same transitions, advantages and targets, new losses): `ppo.learn`."""
    network, settings = setup.network, setup.experiment.ppo

    def run(runner: Runner, transitions: Transition, advantages, targets, losses):
        runner, losses = learn(runner, transitions, advantages, targets, network=network, settings=settings)
        return runner, transitions, advantages, targets, losses

    return run


def scoring_phase(setup: UpdateSetup, curriculum: CurriculumSettings) -> Callable:
    """(params, key, buffer) -> (the same params, the next key, the refreshed buffer): one refresh of SFL's
    buffer (`rl.curricula.sfl.refresh_buffer`) with `curriculum`'s settings, its candidates drawn from the pool."""
    parts = {"env": setup.env, "network": setup.network, "fresh": None, "curriculum": curriculum}

    def run(params, key, buffer):
        key, k_refresh = jax.random.split(key)
        update = jnp.zeros((), jnp.int32)
        buffer = refresh_buffer(params, setup.env_params, setup.pool, k_refresh, **parts, buffer=buffer, update=update)
        return params, key, buffer

    return run


def host_sync_ms(transitions: Transition, finished: jax.Array, losses: dict) -> float:
    """Median time of `jax.device_get` of the update's metrics dict (`ppo.rollout_metrics`) and its conversion
    to floats, as `rl.record` reads it, each time of metrics just computed (a fetched array caches its host
    copy) [ms]."""
    metrics_of = jax.jit(rollout_metrics)
    times = []
    for _ in range(SYNC_REPEATS):
        metrics = jax.block_until_ready(metrics_of(transitions, finished, losses))
        start = time.perf_counter()
        _ = {k: float(v) for k, v in jax.device_get(metrics).items()}
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1e3


# --- what the phases measure with ----------------------------------------------------------------------------


def env_only_rate(setup: UpdateSetup, min_time: float, seed: int, levels: int) -> float:
    """The environment alone at the update's envs, steps per call, size and observation, on the same random
    level pool (`bench.env.bench_env`) [env steps/s]."""
    env, ppo = setup.experiment.env, setup.experiment.ppo
    config = EnvBenchConfig(
        size=env.size,
        envs=(ppo.num_envs,),
        observations=(env.observation,),
        steps=ppo.num_steps,
        min_time=min_time,
        distinct_levels=levels,
        seed=seed,
    )
    return bench_env(config)[0].steps_per_s


def matmul_shapes(setup: UpdateSetup, obs: Any) -> list[tuple[int, int, int]]:
    """The update's dominant matmuls as (rows, inner, cols): the first layer, (minibatch rows x entities) x
    (observation features) x width (a flat model reads the whole observation of a row), and the hidden layers,
    minibatch rows x width x width."""
    rows, width = setup.experiment.ppo.minibatch_size, setup.experiment.model.width
    floats = [x for x in jax.tree.leaves(obs) if jnp.issubdtype(x.dtype, jnp.floating)]
    if setup.experiment.model.name == "flat-mlp":
        first = (rows, sum(math.prod(x.shape[1:]) for x in floats), width)
    else:
        widest = max((x for x in floats if x.ndim >= 3), key=lambda x: x.shape[-1])
        first = (rows * math.prod(widest.shape[1:-1]), widest.shape[-1], width)
    return [first, (rows, width, width)]


def matmul_limits(shapes: list[tuple[int, int, int]], min_time: float) -> list[MatmulRate]:
    """`matmul_rate` of every shape in float32 and in bfloat16."""
    return [matmul_rate(shape, dtype, min_time) for shape in shapes for dtype in (jnp.float32, jnp.bfloat16)]


def matmul_rate(shape: tuple[int, int, int], dtype, min_time: float) -> MatmulRate:
    """A jitted (rows, inner) @ (inner, cols) matmul timed for `min_time` seconds. Each call is a loop of
    products of `MATMUL_OPERANDS` distinct left operands, long enough to last `MATMUL_CALL_S` (found by
    doubling), so that the dispatch of a call does not count. The rate is the fastest call's: a limit, which a
    shared machine's slower moments would otherwise pull below what the update itself achieves (seen here: a
    median limit of 8.2 GFLOP/s beside an update at 13.1)."""
    rows, inner, cols = shape
    k_left, k_right = jax.random.split(jax.random.key(0))
    left = jax.random.normal(k_left, (MATMUL_OPERANDS, rows, inner), dtype)
    right = jax.random.normal(k_right, (inner, cols), dtype)
    carry = (left, right, jnp.zeros((MATMUL_OPERANDS, rows, cols), dtype))
    count = _products_lasting(carry, MATMUL_CALL_S)
    flops = count * 2 * rows * inner * cols
    _, rate, _ = time_calls(_products, (*carry, jnp.int32(count)), flops, min_time, statistic=max)
    return MatmulRate(shape, jnp.dtype(dtype).name, rate / 1e9)


def _products(left: jax.Array, right: jax.Array, out: jax.Array, count: jax.Array) -> tuple:
    """`count` products `left[i % n] @ right` (n = len(left)), each written to `out[i % n]`; `carry -> carry`."""

    def product(i, out):
        k = i % left.shape[0]
        return jax.lax.dynamic_update_index_in_dim(out, left[k] @ right, k, 0)

    return left, right, jax.lax.fori_loop(0, count, product, out), count


def _products_lasting(carry: tuple, seconds: float) -> int:
    """The smallest power of two of products (`_products`) whose call lasts `seconds` (at most 2**20)."""
    count = 1
    compiled = jax.jit(_products).lower(*carry, jnp.int32(count)).compile()  # time_calls finds it in the cache
    while count < 2**20:
        start = time.perf_counter()
        jax.block_until_ready(compiled(*carry, jnp.int32(count)))
        if time.perf_counter() - start >= seconds:
            break
        count *= 2
    return count


def loops_counted() -> bool:
    """Whether XLA's cost analysis multiplies a loop's body by its trip count (a tiny scan of 8 matmuls)."""
    x = jnp.ones((8, 8), jnp.float32)
    one = xla_flops(jax.jit(lambda x: x @ x).lower(x).compile())
    looped = jax.jit(lambda x: jax.lax.scan(lambda c, _: (c @ x, None), x, None, length=8)[0])
    return xla_flops(looped.lower(x).compile()) > 4 * one


def xla_flops(compiled) -> float:
    """The 'flops' of a compiled function's XLA cost analysis: a dict, or a list of dicts (summed) in some JAX
    versions; 0 when XLA gives none."""
    cost = compiled.cost_analysis()
    entries = cost if isinstance(cost, list | tuple) else [cost]
    return float(sum((entry or {}).get("flops", 0.0) for entry in entries))


def _phase(fn: Callable, carry: tuple, trips: int, counted: bool, min_time: float) -> tuple[float, float]:
    """(median ms per call, FLOPs per call) of a `carry -> carry` phase whose loops run `trips` times."""
    _, rate, _ = time_calls(fn, carry, 1, min_time)
    flops = xla_flops(jax.jit(fn).lower(*carry).compile())  # cached by time_calls: nothing compiles here
    return 1e3 / rate, flops * (1 if counted else trips)


def _rollout(setup: UpdateSetup) -> Callable:
    """runner -> (runner, transitions, finished returns): the update's rollout (`ppo.collect`)."""
    ppo = setup.experiment.ppo
    restart = functools.partial(draw_levels, setup.pool, count=ppo.num_envs)
    play = functools.partial(collect, env=setup.env, network=setup.network, num_steps=ppo.num_steps)
    return lambda runner: play(runner, setup.env_params, restart)


def _zero_losses(setup: UpdateSetup, runner: Runner, transitions: Transition, advantages, targets) -> dict:
    """Zeros shaped as `ppo.learn`'s losses (traced, nothing runs)."""
    shapes = jax.eval_shape(learn_phase(setup), runner, transitions, advantages, targets, None)[-1]
    return jax.tree.map(lambda s: jnp.zeros(s.shape, s.dtype), shapes)


def _zero() -> jax.Array:
    return jnp.zeros((), jnp.float32)


def _total(tree) -> jax.Array:
    """The sum of every leaf of `tree`, as one float32 scalar."""
    return sum(jnp.sum(x.astype(jnp.float32)) for x in jax.tree.leaves(tree))
