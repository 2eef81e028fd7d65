"""`kinetix bench train`: PPO training throughput and compile time per model.

One measurement compiles the whole jitted PPO update of `kinetix_cli.ppo` (rollout of `num_steps` steps in
`envs` environments, GAE, `epochs` x `minibatches` gradient steps) for one model and observation, then runs
updates for at least `min_time` seconds. Env steps/s = envs x num_steps / seconds per update (median).
The environments reset to random full levels of the size (`bench.random_levels`: every slot used), the
heaviest case for the engine and for the entity models.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import jax

from engine import SIZES
from kinetix_cli.bench import random_levels, time_calls
from kinetix_cli.config import EnvSettings, ExperimentConfig, ModelSettings, PPOSettings
from kinetix_cli.errors import UserError

# The observation each model reads.
MODEL_OBSERVATION = {"flat-mlp": "symbolic-flat", "pi-mlp": "symbolic-entity", "transformer": "symbolic-entity"}


@dataclasses.dataclass(frozen=True)
class TrainBenchConfig:
    """What to measure for `kinetix bench train`.

    Attributes:
        size: 's', 'm' or 'l'.
        models: model names ('flat-mlp', 'pi-mlp', 'transformer').
        envs: numbers of parallel environments.
        num_steps: rollout length per environment per update.
        epochs, minibatches: PPO passes over each rollout and minibatches per pass.
        width, layers: hidden width (entity encoders, transformer, heads) and actor/critic hidden layers.
        min_time: seconds of timed updates per measurement (at least 2 updates).
        distinct_levels: random full levels the environments reset to.
        seed: seed of the levels, parameters and actions.
    """

    size: str = "s"
    models: tuple[str, ...] = ("flat-mlp", "pi-mlp", "transformer")
    envs: tuple[int, ...] = (64,)
    num_steps: int = 32
    epochs: int = 4
    minibatches: int = 4
    width: int = 128
    layers: int = 5
    min_time: float = 5.0
    distinct_levels: int = 128
    seed: int = 0


@dataclasses.dataclass
class TrainBenchResult:
    """One measurement: whole PPO updates (rollout, GAE, epochs) in environment steps per second."""

    model: str
    observation: str
    size: str
    envs: int
    parameters: int
    compile_s: float
    steps_per_s: float
    calls: int


def experiment_for(config: TrainBenchConfig, model: str, envs: int) -> ExperimentConfig:
    """The experiment config of one measurement (a single update's worth of steps)."""
    ppo = PPOSettings(
        num_envs=envs,
        num_steps=config.num_steps,
        update_epochs=config.epochs,
        num_minibatches=config.minibatches,
        total_timesteps=envs * config.num_steps,
    )
    return ExperimentConfig(
        env=EnvSettings(size=config.size, observation=MODEL_OBSERVATION[model]),
        model=ModelSettings(name=model, width=config.width, actor_critic_layers=config.layers),
        ppo=ppo,
    )


def bench_train(config: TrainBenchConfig, report: Callable[[TrainBenchResult], None] = lambda r: None):
    """Measure every model and environment count; calls `report` after each measurement."""
    from kinetix_cli.ppo import init_runner, make_optimizer, make_update
    from kinetix_cli.train import environment, hyper, network_for

    if config.size not in SIZES:
        raise UserError(f"--size: unknown size {config.size!r}; choose one of {', '.join(SIZES)}")
    for model in config.models:
        if model not in MODEL_OBSERVATION:
            raise UserError(f"--models: unknown model {model!r}; choose from {', '.join(MODEL_OBSERVATION)}")
    for envs in config.envs:
        if (envs * config.num_steps) % config.minibatches:
            raise UserError(
                f"--minibatches: {config.minibatches} does not divide envs x steps = {envs} x {config.num_steps}"
            )
    pool = random_levels(SIZES[config.size], config.distinct_levels, config.seed)
    results = []
    for model in config.models:
        for envs in config.envs:
            experiment = experiment_for(config, model, envs)
            env, env_params = environment(experiment, pool)
            network = network_for(experiment)
            optimizer = make_optimizer(experiment.ppo.lr, experiment.ppo.max_grad_norm, experiment.ppo.adam_eps)
            update = make_update(env, env_params, network.apply, optimizer, hyper(experiment))
            runner = init_runner(env, env_params, network.init, optimizer, envs, jax.random.key(config.seed))
            compile_s, rate, calls = time_calls(
                lambda r, update=update: (update(r)[0],), (runner,), envs * config.num_steps, config.min_time
            )
            parameters = sum(x.size for x in jax.tree.leaves(runner.params))
            result = TrainBenchResult(
                model, MODEL_OBSERVATION[model], config.size, envs, parameters, compile_s, rate, calls
            )
            results.append(result)
            report(result)
    return results
