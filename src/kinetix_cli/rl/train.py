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

A run is three parts: starting it (`rl.launch`: checks, devices, levels, environment, network, curriculum, the
initial or restored state), recording it (`rl.record`: files, evaluations, checkpoints, wandb, progress, the
wall-clock budget, stop signals) and the loop of PPO updates here, which reads top to bottom.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from kinetix_cli.config import ExperimentConfig, config_to_dict, load_config
from kinetix_cli.env.level import Level
from kinetix_cli.errors import UserError
from kinetix_cli.levels.files import load_level
from kinetix_cli.parallel import is_primary, using
from kinetix_cli.rl.launch import Start, check_run, scoring_key, start_run
from kinetix_cli.rl.ppo import Runner
from kinetix_cli.rl.record import Recorder, evaluator

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

    A SIGTERM or Ctrl-C while it trains ends the run after the update in flight, checkpointed, with `Stopped`
    (`rl.record`); `resume=True` then continues it bit for bit.

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
    run_dir = check_run(config, run_dir, resume)
    start = start_run(config, run_dir, resume, pool, init_params, devices)
    recorder = Recorder(
        config, run_dir, resume, start.first_update, start.curriculum, evaluator(config, devices), progress
    )
    with using(start.mesh), recorder.open():
        runner = start.runner
        if start.clones_first():  # an interrupted run clones again: the same steps, from its seed
            runner = start.cloning.before_ppo(runner, start.key, recorder.clone_log, progress)
            recorder.trained += recorder.cloned_seconds() if is_primary() else 0.0  # counts in run.minutes
        return _updates(start, runner, recorder)


def _updates(start: Start, runner: Runner, recorder: Recorder) -> Runner:
    """The run's PPO updates, from its first (or the resumed one) to its last, its budget's end or a stop."""
    curriculum, env_params = start.curriculum, start.env_params
    for update in recorder.updates():
        pool = start.pool.at(update)
        runner = curriculum.before_update(runner, env_params, pool, scoring_key(start.key, update), update)
        runner, metrics = curriculum.update(runner, env_params, pool)
        runner, metrics = start.clone_beside_ppo(runner, metrics, update)
        record = recorder.measure(update, runner, metrics, start.pool.logged())
        if start.restart is not None:  # run.restart_unsolved_after
            runner, record = start.restart(runner, record, recorder.solved)
        recorder.record(runner, record)
    return runner


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
