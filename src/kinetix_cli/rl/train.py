"""Training runs on disk: `train(config, run_dir)` builds the level pool, the environment and the network, then
loops PPO updates (`kinetix_cli.rl.ppo`) with metrics, evaluation, checkpoints and resume.

A run directory holds:
- `config.yaml`: the resolved experiment config (`kinetix-experiment/1`);
- `versions.json`: library versions and machine;
- `metrics.jsonl`: one JSON object per update (update, env steps of the updates, all env steps including
  scoring rollouts, SPS, return, solve rate, losses; every `run.eval_every` updates also `eval_solve_rate` and
  `eval_return` on `run.eval_levels` (each level's result in `evaluations/<update>.json`, as `kinetix eval
  --json` writes it); with a curriculum the buffer's size, mean score and solve-rate
  percentiles, and the steps spent scoring levels);
- `clone.jsonl` (with `clone.updates`): one JSON object per behaviour-cloning step before PPO (`rl.clone`):
  step, loss, accuracy, seconds;
- `checkpoints/<update>/`: orbax checkpoints of the whole training state (`kinetix_cli.rl.checkpoints`), every
  `run.checkpoint_every` updates and at the end. `resume=True` continues from the latest one and, because the
  whole state is saved, reaches the same parameters as an uninterrupted run.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib.util
import json
import math
import time
import warnings
from collections.abc import Callable
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from kinetix_cli.config import (
    CONFIG_FILENAME,
    ExperimentConfig,
    RunSettings,
    config_to_dict,
    load_config,
    save_config,
)
from kinetix_cli.constants import EVAL_FORMAT, VERSIONS_FORMAT
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import Level, to_host
from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_write_json, atomic_write_text, check_output_dir, write_reason
from kinetix_cli.levels.files import level_paths, load_level
from kinetix_cli.parallel import (
    check_divisible,
    is_primary,
    make_mesh,
    primary_decides,
    replicate,
    sync,
    using,
)
from kinetix_cli.provenance import environment_info
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.checkpoints import (
    CHECKPOINTS,
    checkpoint_manager,
    restore_runner,
    save_runner,
    writing,
)
from kinetix_cli.rl.clone import Cloning, load_demonstrations
from kinetix_cli.rl.curricula import curriculum_class, make_curriculum
from kinetix_cli.rl.evaluate import Evaluator, evaluation_record
from kinetix_cli.rl.networks import CRITIC, POLICY_HEAD, replace_subtrees, temper, training_network
from kinetix_cli.rl.pool import fresh_source, level_pool
from kinetix_cli.rl.ppo import Runner, init_runner, make_optimizer
from kinetix_cli.rl.trees import tree_mismatch

METRICS_FILE = "metrics.jsonl"
CLONE_FILE = "clone.jsonl"
VERSIONS_FILE = "versions.json"
EVALUATIONS = "evaluations"
"""Folder of a run's evaluations during training: `<update>.json`, each as `kinetix eval --json` writes it."""
INHERITED_ENV = ("observation", "action", "frame_skip")
"""What a fine-tuned agent keeps of its pre-training run's `env` section (besides the whole `model` section): what
it sees, how it acts and how often."""


def train(
    config: ExperimentConfig,
    run_dir: str | Path,
    resume: bool = False,
    progress: Callable[[dict], None] | None = None,
    pool: Level | None = None,
    init_params=None,
    devices: int | None = None,
) -> Runner:
    """Train (or resume) a run in `run_dir`; returns the final training state.

    The run is data-parallel over a 1-D mesh of `devices` local devices of every process (`kinetix_cli.parallel`;
    None: all): environments, rollouts and curriculum scoring are split across the devices, parameters and the
    optimiser state replicated. In a multi-process run every process calls `train` with equal arguments, and
    only the primary one writes the run's files (checkpoints are written by all, through orbax).

    Args:
        config: the experiment.
        run_dir: the run's folder (new or empty, or the run to resume).
        resume: continue from the latest checkpoint.
        progress: called with each update's metrics record.
        pool: the training levels (default: `level_pool(config)`; None with source 'fresh').
        init_params: initial network parameters (fine-tuning); default: those of the checkpoint named by
            `run.init_from`, else freshly initialised.
        devices: local devices per process to train on (None: all).
    """
    run_dir = check_output_dir(run_dir, "--run-dir")
    if config.run.wandb != "off" and importlib.util.find_spec("wandb") is None:
        raise UserError(
            f"run.wandb={config.run.wandb}: wandb is not installed; install it with pip install 'kinetix[wandb]' "
            "or leave run.wandb off (metrics.jsonl is written either way)"
        )
    if not resume and run_dir.exists() and any(run_dir.iterdir()):
        raise UserError(f"--run-dir {run_dir}: not empty; pass --resume to continue it or choose a new folder")
    saved = run_dir / CONFIG_FILENAME
    if resume and saved.exists() and not _same_experiment(load_config(saved), config):
        raise UserError(
            f"--resume: {saved} differs from the config given; resume with the run's own config (only "
            "run.minutes may change)"
        )

    # Everything that can fail on bad input happens before anything is written: a failed start leaves no debris.
    mesh = make_mesh(devices)
    _check_split(config, mesh)
    demos = load_demonstrations(config) if config.clone.active else None
    if pool is None:  # each process generates a pool on its own devices: the same levels in every process
        pool = level_pool(config, make_mesh(devices, local_only=True))
    with using(mesh):
        return _train(config, run_dir, resume, progress, pool, init_params, mesh, devices, demos)


def _train(config, run_dir: Path, resume: bool, progress, pool, init_params, mesh, devices, demos) -> Runner:
    saved = run_dir / CONFIG_FILENAME
    evaluator = _evaluator(config, devices)
    pool = None if pool is None else replicate(pool, mesh)
    fresh = fresh_source(config)
    env, env_params = make_env(config.env, pairs=config.trains_on_pairs)
    env_params = replicate(env_params, mesh)
    network = training_network(config)
    cloning = None if demos is None else Cloning(config, *demos, mesh, network)
    settings = config.ppo
    curriculum = make_curriculum(config.curriculum, env=env, network=network, ppo=settings, fresh=fresh)
    key = replicate(jax.random.key(config.run.seed), mesh)
    runner = init_runner(env, network, settings, pool, key, fresh=fresh, buffer_size=curriculum.buffer_size)
    origin = f"--from {config.run.init_from}" if init_params is not None else f"run.init_from {config.run.init_from}"
    if init_params is None and config.run.init_from:
        init_params = load_policy(config.run.init_from).params
    restart_at, fallback = config.run.restart_unsolved_after, None
    if init_params is not None:
        if restart_at:  # what the run starts again from if its first updates solve nothing: the features alone
            alone = dataclasses.replace(config.run, fresh_policy_head=True, fresh_critic=True, policy_temperature=1.0)
            fallback = _with_params(runner, replicate(init_params, mesh), settings, origin, alone)
        runner = _with_params(runner, replicate(init_params, mesh), settings, origin, config.run)
    start = 0
    if resume and (run_dir / CHECKPOINTS).is_dir():
        with checkpoint_manager(run_dir, read_only=True) as reader:
            if reader.latest_step() is not None:
                start = int(reader.latest_step())
                runner = restore_runner(reader, start, runner)

    sync("checked")  # every process has read the run before the primary writes to it
    primary = is_primary()
    try:
        if primary:
            run_dir.mkdir(parents=True, exist_ok=True)
            save_config(config, saved)
            atomic_write_json(run_dir / VERSIONS_FILE, environment_info(), VERSIONS_FORMAT)
            _truncate_metrics(run_dir / METRICS_FILE, start)  # a resumed run keeps only the lines it will not redo
        sync("prepared")
        manager = checkpoint_manager(run_dir)
        logger = _wandb_run(config, run_dir, resume) if primary else None
        log = open(run_dir / METRICS_FILE, "a") if primary else contextlib.nullcontext()  # noqa: SIM115
    except OSError as exc:
        raise UserError(f"--run-dir {run_dir}: cannot write: {exc.strerror or exc}") from None
    kept = start or None  # the last complete checkpoint
    pool_every, pool_round = config.levels.refresh_every, 0
    budget = config.run.minutes * 60  # 0: none; the primary's clock decides for every process
    trained = (
        _trained_seconds(run_dir / METRICS_FILE, settings) + _cloned_seconds(run_dir) if start and primary else 0.0
    )
    spent = bool(budget) and primary_decides("budget", trained >= budget)  # a resumed run that had used it up
    solved = _solved_episodes(run_dir / METRICS_FILE) if start and primary else 0.0
    if cloning is not None and config.clone.updates and start == 0:  # behaviour cloning first (an interrupted run
        # clones again: the same steps, from its seed); its time counts in run.minutes
        runner = cloning.before_ppo(runner, key, run_dir / CLONE_FILE if primary else None, progress)
        trained += _cloned_seconds(run_dir) if primary else 0.0
    with log, writing(manager):
        for u in range(start, start if spent else settings.num_updates):
            tic = time.perf_counter()
            if pool_every and u // pool_every != pool_round:  # a new generated pool (a resumed run: its round's)
                pool_round = u // pool_every
                pool = replicate(level_pool(config, make_mesh(devices, local_only=True), pool_round), mesh)
            runner = curriculum.before_update(runner, env_params, pool, _scoring_key(key, u), u)
            runner, metrics = curriculum.update(runner, env_params, pool)
            if cloning is not None and config.clone.coef:
                runner, cloned = cloning.beside_ppo(runner, _cloning_key(key, u))
                metrics |= cloned
            metrics = curriculum.logged({k: float(v) for k, v in jax.device_get(metrics).items()})
            seconds = time.perf_counter() - tic
            steps = (u + 1) * settings.batch_size
            record = {"update": u + 1, "steps": steps, "sps": settings.batch_size / seconds} | metrics
            record |= curriculum.metrics(runner, steps)
            record |= {"pool_round": pool_round} if pool_every else {}
            if not all(math.isfinite(v) for v in metrics.values()):
                bad = sorted(k for k, v in metrics.items() if not math.isfinite(v))
                raise UserError(
                    f"{run_dir}: update {u + 1}: {', '.join(bad)} not finite: training diverged (ppo.lr "
                    f"{settings.lr:g}, max_grad_norm {settings.max_grad_norm:g}); nothing of this update was kept"
                )
            trained += seconds
            solved += metrics["solve_rate"] * metrics["episodes"]
            if fallback is not None and u + 1 == restart_at and primary_decides("restart", solved == 0):
                runner = runner.replace(params=fallback.params, opt_state=fallback.opt_state)
                record["restarted"] = 1.0
            out_of_time = bool(budget) and primary_decides("budget", trained >= budget)
            last = u + 1 == settings.num_updates or out_of_time
            evaluation = None
            if evaluator is not None and ((u + 1) % config.run.eval_every == 0 or last):
                evaluation = _evaluation(evaluator, runner.params, config.run, run_dir, u + 1)
                record |= _evaluation_metrics(evaluation)
            try:
                if primary:
                    if evaluation is not None:
                        atomic_write_json(run_dir / EVALUATIONS / f"{u + 1}.json", evaluation, EVAL_FORMAT)
                    log.write(json.dumps(record) + "\n")
                    log.flush()
                every = config.run.checkpoint_every
                if (every and (u + 1) % every == 0) or last:
                    save_runner(manager, u + 1, runner)
                    kept = u + 1
            except (OSError, UserError, ValueError) as exc:  # orbax reports a failed write as a ValueError
                raise _write_failed(run_dir, u + 1, exc, kept) from None
            if logger is not None:
                logger.log(record, step=steps)
            if progress is not None and primary:
                progress(record)
            if last:
                break
    if logger is not None:
        logger.finish()
    return runner


def _same_experiment(saved: ExperimentConfig, given: ExperimentConfig) -> bool:
    """Whether `given` continues the run of `saved`: equal but for the wall-clock budget, which a resumed run may
    extend (the run then trains until its total training time passes the new one)."""
    budget = dataclasses.replace(given.run, minutes=saved.run.minutes)
    return saved == dataclasses.replace(given, run=budget)


def _write_failed(run_dir: Path, update: int, exc: Exception, kept: int | None) -> UserError:
    """The one line for a write that failed during the run (a full disk, a quota, a folder made read-only): what
    failed, and what is kept: every complete checkpoint and the metrics up to the last one (`checkpoints.writing`
    removes the partial checkpoint)."""
    if kept is None:
        after = "no checkpoint was complete yet; once the folder can be written, rerun with --resume to start again"
    else:
        after = (
            f"the last complete checkpoint ({kept}) is kept; once the folder can be written, rerun with --resume "
            "to continue from it"
        )
    return UserError(f"--run-dir {run_dir}: cannot write update {update}: {write_reason(exc)}; {after}")


def _check_split(config: ExperimentConfig, mesh) -> None:
    """One clear line unless every batch the run splits across devices splits evenly."""
    check_divisible(config.ppo.num_envs, mesh, "ppo.num_envs")
    if config.clone.active:
        check_divisible(config.clone.batch, mesh, "clone.batch")
    curriculum_class(config.curriculum).check_split(config.curriculum, mesh)


def finetune_config(
    path: Path,
    files: list[Path],
    pretrained: ExperimentConfig | None,
    overrides: list[str] | tuple[str, ...] = (),
    init_from: str | None = None,
) -> ExperimentConfig:
    """The experiment of `kinetix finetune`: the config file `path`, training on and evaluating on the level
    `files` (one size), with the model and `INHERITED_ENV` of the `pretrained` run's config (None: from scratch)
    and `run.init_from` naming where its parameters came from (`--from`); `overrides` (`--set`) win over all of
    it."""
    sizes = {load_level(file).default_size() for file in files}
    if len(sizes) != 1:
        raise UserError(f"finetune: the levels have sizes {', '.join(sorted(sizes))}; give levels of one size")
    listed = "[" + ", ".join(str(file) for file in files) + "]"
    settings = [f"env.size={sizes.pop()}", "levels.source=files", f"levels.files={listed}"]
    settings += [f"run.eval_levels={listed}"]  # evaluate on the fine-tuning levels
    if pretrained is not None:
        inherited = config_to_dict(pretrained)
        settings += [f"env.{key}={inherited['env'][key]}" for key in INHERITED_ENV]
        settings += [f"model.{key}={value}" for key, value in inherited["model"].items()]
    if init_from is not None:
        settings += [f"run.init_from={json.dumps(str(init_from))}"]  # quoted: any name or path stays a string
    return load_config(path, [*settings, *overrides])


def _with_params(runner: Runner, params, settings, origin: str, run: RunSettings) -> Runner:
    """The runner with `params` (from a checkpoint) and a fresh optimiser state; the network must match (else an
    error naming `origin`, the flag or key and where the parameters came from). With `run.fresh_policy_head` the
    actor's output layer keeps the runner's own fresh initialisation; `run.policy_temperature` scales it by
    1 / temperature (logits divided by it); with `run.fresh_critic` the critic keeps the runner's own."""
    why = tree_mismatch(runner.params, params)
    if why is not None:
        raise UserError(f"{origin}: the checkpoint's network does not match this run's model settings ({why})")
    params = jax.tree.map(jnp.asarray, params)
    if run.fresh_policy_head:
        params = replace_subtrees(params, runner.params, POLICY_HEAD)
    if run.policy_temperature != 1.0:
        params = temper(params, run.policy_temperature)
    if run.fresh_critic:
        for name in CRITIC:
            params = replace_subtrees(params, runner.params, name)
    return runner.replace(params=params, opt_state=make_optimizer(settings).init(params))


def _cloning_key(run_key: jax.Array, update: int) -> jax.Array:
    """The key of the cloning step after `update`: a stream of its own, a function of the update only."""
    return jax.random.fold_in(jax.random.fold_in(run_key, 2), update)


def _scoring_key(run_key: jax.Array, update: int) -> jax.Array:
    """The key of the curriculum's work before `update`: a stream of its own, a function of the update only,
    so a resumed run scores exactly as an uninterrupted one."""
    return jax.random.fold_in(jax.random.fold_in(run_key, 1), update)


def _evaluator(config: ExperimentConfig, devices: int | None) -> Evaluator | None:
    """The evaluator of `run.eval_levels` (loaded once; each process evaluates on its `devices` local devices),
    or None when training does not evaluate."""
    if not (config.run.eval_every and config.run.eval_levels):
        return None
    return Evaluator(config, level_paths(config.run.eval_levels), config.run.eval_attempts, devices)


def _evaluation(evaluator: Evaluator, params, run, run_dir: Path, update: int) -> dict:
    """The evaluation of `params` on the run's evaluation levels (`kinetix eval --json`'s record). The sampling
    seed is the run's, so a resumed run evaluates exactly as an uninterrupted one."""
    results = evaluator(to_host(params), run.seed)
    return evaluation_record(str(run_dir), update, run.eval_attempts, run.seed, results)


def _evaluation_metrics(evaluation: dict) -> dict:
    """Mean solve rate and return over the evaluation levels, for the metrics record."""
    levels = evaluation["levels"]
    return {
        "eval_solve_rate": float(np.mean([r["solve_rate"] for r in levels])),
        "eval_return": float(np.mean([r["mean_return"] for r in levels])),
    }


def _wandb_run(config: ExperimentConfig, run_dir: Path, resume: bool):
    """A wandb run when `run.wandb` is 'offline' or 'online', else None. wandb is an optional extra (`train`
    refuses to start without it); if it cannot start (no network, ...), training goes on with a warning;
    metrics.jsonl is always written."""
    if config.run.wandb == "off":
        return None
    try:
        import wandb  # optional and slow to import: only when asked for

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


def _logged(path: Path) -> list[dict]:
    """The update records of a run's `metrics.jsonl` (none before the first)."""
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]


def _trained_seconds(path: Path, settings) -> float:
    """Training time of the updates logged in `metrics.jsonl` [s], rebuilt from each one's steps per second (what
    `run.minutes` counts, the first update's compile included; a resumed run goes on from it)."""
    return sum(settings.batch_size / record["sps"] for record in _logged(path))


def _cloned_seconds(run_dir: Path) -> float:
    """Time of the behaviour-cloning steps before PPO logged in the run's `clone.jsonl` [s] (0 without)."""
    return sum(record["seconds"] for record in _logged(run_dir / CLONE_FILE))


def _solved_episodes(path: Path) -> float:
    """Training episodes solved in the updates logged in `metrics.jsonl` (`run.restart_unsolved_after`)."""
    return sum(record["solve_rate"] * record["episodes"] for record in _logged(path))


def _truncate_metrics(path: Path, last_update: int) -> None:
    """Keep the metric lines of updates up to `last_update` (the checkpoint a run resumes from; 0 before the
    first); a torn line from a kill mid-write is dropped with the rest."""
    if not path.exists():
        return
    kept = []
    for line in path.read_text(encoding="utf-8", errors="replace").splitlines():
        try:
            record = json.loads(line)
        except json.JSONDecodeError:
            continue
        if isinstance(record, dict) and isinstance(record.get("update"), int) and record["update"] <= last_update:
            kept.append(line)
    atomic_write_text(path, "".join(line + "\n" for line in kept))
