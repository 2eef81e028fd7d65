"""`kinetix bench train`: PPO training throughput and compile time per model.

One measurement compiles the whole jitted PPO update of `kinetix_cli.rl.ppo` (rollout of `num_steps` steps in
`envs` environments, GAE, `epochs` x `minibatches` gradient steps) for one model and observation, then runs
updates for at least `min_time` seconds. Env steps/s = envs x num_steps / seconds per update (median).
The environments reset to random full levels of the size (`bench.env.random_levels`: every slot used), the
heaviest case for the engine and for the entity models. Each model reads its first observation type in
`constants.MODEL_OBSERVATIONS`. With several device counts (`devices`), each is measured on a mesh of that many
local devices (`kinetix_cli.parallel`), the environments split across them.

With `breakdown`, each measurement also says where the update's time goes (`bench.breakdown`: the environment
alone, each phase alone, FLOPs and the machine's matmul limit, and with `score_levels` SFL's scoring beside it),
on one device. With `trace`, a JAX profiler trace of `TRACE_UPDATES` updates of each measurement is written under
that folder, one subfolder per measurement (`trace_name`).
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable
from pathlib import Path

import jax

from engine import SIZES
from kinetix_cli.bench.breakdown import Breakdown, UpdateSetup, measure_breakdown, trace_updates
from kinetix_cli.bench.env import random_levels
from kinetix_cli.bench.timing import time_calls
from kinetix_cli.config import CurriculumSettings, EnvSettings, ExperimentConfig, ModelSettings, PPOSettings
from kinetix_cli.constants import COMPUTE_TYPES, MODEL_NAMES, MODEL_OBSERVATIONS
from kinetix_cli.env.factory import make_env
from kinetix_cli.errors import UserError
from kinetix_cli.io import check_output_dir
from kinetix_cli.parallel import check_divisible, make_mesh, replicate, using
from kinetix_cli.rl.networks import make_network, parameter_count
from kinetix_cli.rl.ppo import init_runner, ppo_update

TRACE_UPDATES = 3
"""Updates in each measurement's profiler trace (`trace`), after the timed ones (compiled already)."""


@dataclasses.dataclass(frozen=True)
class TrainBenchConfig:
    """What to measure for `kinetix bench train`.

    Attributes:
        size: 's', 'm' or 'l'.
        models: model names (`constants.MODEL_NAMES`: 'flat-mlp', 'pi-mlp', 'rel-mlp', 'transformer').
        envs: numbers of parallel environments.
        num_steps: rollout length per environment per update.
        epochs, minibatches: PPO passes over each rollout and minibatches per pass.
        width, layers: hidden width (entity encoders, transformer, heads) and actor/critic hidden layers.
        computes: number types the networks compute in (`model.compute`: 'float32', 'bfloat16'), each measured.
        min_time: seconds of timed updates per measurement (at least 2 updates).
        distinct_levels: random full levels the environments reset to.
        seed: seed of the levels, parameters and actions.
        devices: local device counts to measure on (None: all local devices; 1 with `breakdown`).
        breakdown: also measure where each update's time goes (`bench.breakdown`; one device only).
        trace: folder for a JAX profiler trace of each measurement's updates (None: no trace).
        score_levels, score_attempts, score_steps, refresh_every: with `breakdown`, SFL's scoring timed beside the
            update with these `curriculum` settings (`scoring_settings`); 0 levels: none.
    """

    size: str = "s"
    models: tuple[str, ...] = ("flat-mlp", "pi-mlp", "transformer")
    envs: tuple[int, ...] = (64,)
    num_steps: int = 32
    epochs: int = 4
    minibatches: int = 4
    width: int = 128
    layers: int = 5
    computes: tuple[str, ...] = ("float32",)
    min_time: float = 5.0
    distinct_levels: int = 128
    seed: int = 0
    devices: tuple[int, ...] | None = None
    breakdown: bool = False
    trace: str | None = None
    score_levels: int = 0
    score_attempts: int = 2
    score_steps: int = 256
    refresh_every: int = 64


@dataclasses.dataclass
class TrainBenchResult:
    """One measurement: whole PPO updates (rollout, GAE, epochs) in environment steps per second (`steps_per_s`,
    the median), with `breakdown` where the update's time goes and `trace` the folder of its profiler trace."""

    model: str
    observation: str
    size: str
    envs: int
    parameters: int
    compile_s: float
    steps_per_s: float
    calls: int
    devices: int = 1
    breakdown: Breakdown | None = None
    trace: str | None = None
    compute: str = "float32"


def experiment_for(config: TrainBenchConfig, model: str, envs: int, compute: str = "float32") -> ExperimentConfig:
    """The experiment config of one measurement (a single update's worth of steps)."""
    ppo = PPOSettings(
        num_envs=envs,
        num_steps=config.num_steps,
        update_epochs=config.epochs,
        num_minibatches=config.minibatches,
        total_timesteps=envs * config.num_steps,
    )
    return ExperimentConfig(
        env=EnvSettings(size=config.size, observation=MODEL_OBSERVATIONS[model][0]),
        model=ModelSettings(name=model, width=config.width, actor_critic_layers=config.layers, compute=compute),
        ppo=ppo,
    )


def scoring_settings(config: TrainBenchConfig) -> CurriculumSettings | None:
    """SFL's settings whose scoring the breakdown times (None: none asked for): the candidates drawn in one batch,
    a buffer of at most the default size (its cost is the top-k of the scores)."""
    if not config.score_levels:
        return None
    return CurriculumSettings(
        name="sfl",
        score_levels=config.score_levels,
        score_batch=config.score_levels,
        score_steps=config.score_steps,
        score_attempts=config.score_attempts,
        buffer_size=min(config.score_levels, CurriculumSettings.buffer_size),
        refresh_every=config.refresh_every,
    )


def bench_train(config: TrainBenchConfig, report: Callable[[TrainBenchResult], None] = lambda r: None):
    """Measure every model and environment count; calls `report` after each measurement."""
    if config.size not in SIZES:
        raise UserError(f"--size: unknown size {config.size!r}; choose one of {', '.join(SIZES)}")
    for model in config.models:
        if model not in MODEL_NAMES:
            raise UserError(f"--models: unknown model {model!r}; choose from {', '.join(MODEL_NAMES)}")
    for compute in config.computes:
        if compute not in COMPUTE_TYPES:
            raise UserError(f"--compute: unknown number type {compute!r}; choose from {', '.join(COMPUTE_TYPES)}")
    for envs in config.envs:
        if (envs * config.num_steps) % config.minibatches:
            raise UserError(
                f"--minibatches: {config.minibatches} does not divide envs x steps = {envs} x {config.num_steps}"
            )
    meshes = [make_mesh(count) for count in config.devices or [1 if config.breakdown else None]]
    for mesh in meshes:
        for envs in config.envs:
            check_divisible(envs, mesh, "--envs")
        if config.breakdown and mesh.size > 1:
            raise UserError(f"--breakdown: measures on one device, not {mesh.size}; add --devices 1")
    if config.trace is not None:
        check_output_dir(config.trace, "--trace")
    pool = random_levels(SIZES[config.size], config.distinct_levels, config.seed)
    results = []
    for model in config.models:
        for envs in config.envs:
            for compute in config.computes:
                for mesh in meshes:
                    with using(mesh):
                        result = _measure(config, model, envs, compute, replicate(pool, mesh), mesh)
                    results.append(result)
                    report(result)
    return results


def _measure(config: TrainBenchConfig, model: str, envs: int, compute: str, pool, mesh) -> TrainBenchResult:
    experiment = experiment_for(config, model, envs, compute)
    env, env_params = make_env(
        experiment.env, pairs=experiment.model.reads_pairs, attention=experiment.model.reads_attention
    )
    network = make_network(experiment.model, experiment.env)
    update = functools.partial(ppo_update, env=env, network=network, settings=experiment.ppo)
    runner = init_runner(env, network, experiment.ppo, pool, replicate(jax.random.key(config.seed), mesh))
    step = functools.partial(update, env_params=replicate(env_params, mesh), levels=pool)
    one_update = lambda r: (step(r)[0],)  # noqa: E731  (one function: the breakdown and trace reuse its compile)
    compile_s, rate, calls = time_calls(one_update, (runner,), envs * config.num_steps, config.min_time)
    parameters = parameter_count(runner.params)
    observation = experiment.env.observation
    result = TrainBenchResult(
        model, observation, config.size, envs, parameters, compile_s, rate, calls, mesh.size, compute=compute
    )
    if config.breakdown:
        setup = UpdateSetup(experiment, env, env_params, network, pool)
        update_ms = 1e3 * envs * config.num_steps / rate
        result.breakdown = measure_breakdown(
            setup,
            runner,
            one_update,
            update_ms,
            config.min_time,
            config.seed,
            config.distinct_levels,
            scoring_settings(config),
        )
    if config.trace is not None:
        result.trace = str(Path(config.trace) / trace_name(result))
        trace_updates(one_update, runner, result.trace, TRACE_UPDATES)
    return result


def trace_name(result: TrainBenchResult) -> str:
    """The subfolder of a measurement's trace: model, size, environments, devices, and the number type unless
    float32."""
    compute = "" if result.compute == "float32" else f"-{result.compute}"
    return f"{result.model}-{result.size}-envs{result.envs}-devices{result.devices}{compute}"
