"""Training runs on disk: `train(config, run_dir)` builds the environment, the level pool and the network, then
loops PPO updates (`kinetix_cli.ppo`) with metrics, checkpoints and resume.

A run directory holds:
- `config.yaml`: the resolved experiment config (`kinetix-experiment/1`);
- `versions.json`: library versions and machine;
- `metrics.jsonl`: one JSON object per update (update, env steps, SPS, return, solve rate, losses; every
  `run.eval_every` updates also `eval_solve_rate` and `eval_return` on `run.eval_levels`);
- `checkpoints/<update>/`: orbax checkpoints of the whole training state (parameters, optimiser, environments,
  PRNG key), every `run.checkpoint_every` updates and at the end. `resume=True` continues from the latest one
  and, because the whole state is saved, reaches the same parameters as an uninterrupted run.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from engine import SIZES
from kinetix_cli.config import ExperimentConfig, load_config, save_config
from kinetix_cli.env import EnvConfig, EnvParams, KinetixEnv, reset_from_pool
from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_write_json
from kinetix_cli.level import Level, stack_levels
from kinetix_cli.networks import make_network
from kinetix_cli.ppo import PPOHyper, Runner, init_runner, make_optimizer, make_update

METRICS_FILE = "metrics.jsonl"
CHECKPOINTS = "checkpoints"


def level_pool(config: ExperimentConfig) -> Level:
    """The training levels as one batch: generated (filtered, `pool_size`), a level set, or level files."""
    settings, size = config.levels, config.env.size
    static = SIZES[size]
    if settings.source == "files":
        from kinetix_cli.level_file import load_level

        return stack_levels([load_level(path).build(static) for path in settings.files])
    if settings.source == "levelset":
        from kinetix_cli.levelset import load_levelset

        levelset = load_levelset(settings.levelset)
        if levelset.manifest["size"] != size:
            raise UserError(f"{settings.levelset}: holds size-{levelset.manifest['size']} levels, env.size is {size}")
        return jax.tree.map(jnp.asarray, levelset.levels)
    from kinetix_cli.generate import generate_chunk, make_config

    generation = make_config(size)
    chunks, kept, index = [], 0, 0
    while kept < settings.pool_size:
        levels, _ = generate_chunk(generation, config.run.seed, index)
        chunks.append(levels)
        kept += levels.bindings.motor.shape[0]
        index += 1
    pool = jax.tree.map(lambda *xs: np.concatenate(xs)[: settings.pool_size], *chunks)
    return jax.tree.map(jnp.asarray, pool)


def network_for(config: ExperimentConfig):
    """The flax actor-critic module of the config."""
    m = config.model
    hparams = {"hidden_width": m.width, "hidden_depth": m.actor_critic_layers}
    if m.name == "transformer":
        hparams |= {"width": m.width, "num_layers": m.transformer_layers, "num_heads": m.heads}
    elif m.name == "pi-mlp":
        hparams |= {"width": m.width}
    return make_network(m.name, config.env.action, **hparams)


def environment(config: ExperimentConfig, pool: Level) -> tuple[KinetixEnv, EnvParams]:
    """The environment of the config, resetting to random levels of `pool`."""
    e = config.env
    env_config = EnvConfig(SIZES[e.size], observation=e.observation, action=e.action, frame_skip=e.frame_skip)
    params = EnvParams(max_steps=e.max_steps, dense_reward_scale=e.dense_reward_scale)
    return KinetixEnv(env_config, reset_from_pool(pool)), params


def hyper(config: ExperimentConfig) -> PPOHyper:
    p = config.ppo
    return PPOHyper(
        p.num_envs,
        p.num_steps,
        p.update_epochs,
        p.num_minibatches,
        p.gamma,
        p.gae_lambda,
        p.clip_eps,
        p.ent_coef,
        p.vf_coef,
        p.normalise_advantages,
    )


def _checkpointer(run_dir: Path):
    import orbax.checkpoint as ocp

    return ocp.CheckpointManager(run_dir.resolve() / CHECKPOINTS, options=ocp.CheckpointManagerOptions(max_to_keep=3))


def _to_disk(runner: Runner) -> Runner:
    return runner.replace(key=jax.random.key_data(runner.key))


def _from_disk(runner: Runner) -> Runner:
    return runner.replace(key=jax.random.wrap_key_data(runner.key))


def train(
    config: ExperimentConfig,
    run_dir: str | Path,
    resume: bool = False,
    progress: Callable[[dict], None] | None = None,
    pool: Level | None = None,
    init_params=None,
) -> Runner:
    """Train (or resume) a run in `run_dir`; returns the final training state. `progress(metrics)` is called
    after every update; `init_params` (fine-tuning), else the checkpoint named by `run.init_from`, replaces the
    freshly initialised parameters."""
    import orbax.checkpoint as ocp

    from kinetix_cli.bench import environment_info

    run_dir = Path(run_dir)
    if not resume and run_dir.exists() and any(run_dir.iterdir()):
        raise UserError(f"--run-dir {run_dir}: not empty; pass --resume to continue it or choose a new folder")
    evaluator = _evaluator(config)  # bad evaluation levels fail here, before anything is written
    run_dir.mkdir(parents=True, exist_ok=True)
    saved = run_dir / "config.yaml"
    if resume and saved.exists() and load_config(saved) != config:
        raise UserError(f"--resume: {saved} differs from the config given; resume with the run's own config")
    save_config(config, saved)
    atomic_write_json(run_dir / "versions.json", environment_info(), "kinetix-versions/1")

    pool = level_pool(config) if pool is None else pool
    env, env_params = environment(config, pool)
    network = network_for(config)
    p = config.ppo
    lr = p.lr
    if p.anneal_lr:
        lr = _linear_schedule(p.lr, p.num_updates * p.update_epochs * p.num_minibatches)
    optimizer = make_optimizer(lr, p.max_grad_norm, p.adam_eps)
    update = make_update(env, env_params, network.apply, optimizer, hyper(config))
    runner = init_runner(env, env_params, network.init, optimizer, p.num_envs, jax.random.key(config.run.seed))
    if init_params is None and config.run.init_from:
        from kinetix_cli.evaluate import load_policy

        init_params = load_policy(config.run.init_from)[1]
    if init_params is not None:
        if jax.tree.structure(init_params) != jax.tree.structure(runner.params) or any(
            a.shape != b.shape
            for a, b in zip(jax.tree.leaves(init_params), jax.tree.leaves(runner.params), strict=True)
        ):
            raise UserError("--from: the checkpoint's network does not match this run's model settings")
        init_params = jax.tree.map(jnp.asarray, init_params)
        runner = runner.replace(params=init_params, opt_state=optimizer.init(init_params))

    manager = _checkpointer(run_dir)
    start = 0
    if resume and manager.latest_step() is not None:
        start = int(manager.latest_step())
        restored = manager.restore(start, args=ocp.args.StandardRestore(_to_disk(runner)))
        runner = _from_disk(restored)
        _truncate_metrics(run_dir / METRICS_FILE, start)

    steps_per_update = p.num_envs * p.num_steps
    logger = _wandb_run(config, run_dir, resume)
    with open(run_dir / METRICS_FILE, "a") as log:
        for u in range(start, p.num_updates):
            tic = time.perf_counter()
            runner, metrics = update(runner)
            metrics = {k: float(v) for k, v in jax.device_get(metrics).items()}
            seconds = time.perf_counter() - tic
            record = {"update": u + 1, "steps": (u + 1) * steps_per_update, "sps": steps_per_update / seconds}
            record |= metrics
            if evaluator is not None and ((u + 1) % config.run.eval_every == 0 or u + 1 == p.num_updates):
                record |= _evaluation(evaluator, runner.params, config.run.seed)
            log.write(json.dumps(record) + "\n")
            log.flush()
            every = config.run.checkpoint_every
            if (every and (u + 1) % every == 0) or u + 1 == p.num_updates:
                manager.save(u + 1, args=ocp.args.StandardSave(_to_disk(runner)))
                manager.wait_until_finished()  # a kill after this point loses no finished update
            if logger is not None:
                logger.log(record, step=record["steps"])
            if progress is not None:
                progress(record)
    if logger is not None:
        logger.finish()
    return runner


def _evaluator(config: ExperimentConfig):
    """The evaluator of `run.eval_levels` (loaded and compiled once), or None when training does not evaluate."""
    if not (config.run.eval_every and config.run.eval_levels):
        return None
    from kinetix_cli.evaluate import Evaluator
    from kinetix_cli.level_file import level_paths

    return Evaluator(config, level_paths(config.run.eval_levels), config.run.eval_attempts)


def _evaluation(evaluator, params, seed: int) -> dict:
    """Mean solve rate and return over the evaluation levels, for the metrics record. The sampling seed is the
    run's, so a resumed run evaluates exactly as an uninterrupted one."""
    results = evaluator(params, seed)
    return {
        "eval_solve_rate": float(np.mean([r.solve_rate for r in results])),
        "eval_return": float(np.mean([r.mean_return for r in results])),
    }


def _wandb_run(config: ExperimentConfig, run_dir: Path, resume: bool):
    """A wandb run when `run.wandb` is 'offline' or 'online', else None. wandb is optional: if it cannot start
    (not installed, no network), training goes on with a warning; metrics.jsonl is always written."""
    if config.run.wandb == "off":
        return None
    import dataclasses
    import warnings

    try:
        import wandb

        return wandb.init(
            project="kinetix",
            name=run_dir.name,
            dir=str(run_dir),
            mode=config.run.wandb,
            config=dataclasses.asdict(config),
            resume="allow" if resume else None,
        )
    except Exception as exc:  # any failure to start logging must not stop training
        warnings.warn(
            f"wandb did not start ({type(exc).__name__}: {exc}); metrics go to metrics.jsonl only", stacklevel=2
        )
        return None


def _linear_schedule(lr: float, total: int):
    return lambda count: lr * (1.0 - jnp.minimum(count, total) / total)


def _truncate_metrics(path: Path, last_update: int) -> None:
    """Drop metric lines written after the checkpoint a run resumes from."""
    if not path.exists():
        return
    lines = [line for line in path.read_text().splitlines() if line and json.loads(line)["update"] <= last_update]
    path.write_text("".join(line + "\n" for line in lines))
