"""Recording a training run: its files (config, versions, metrics, evaluations, checkpoints), wandb, progress, the
wall-clock budget, and a stop asked for by a signal.

`Recorder` is the half of `rl.train`'s loop that does not train: `updates()` yields the updates to run (timing
each), `measure` turns an update's metrics into its record, `record` evaluates, writes and checkpoints it.

A run told to stop (SIGTERM from a scheduler, or Ctrl-C) finishes the update in flight, checkpoints it and ends;
`train` then raises `Stopped`, and `--resume` continues bit for bit. A second signal of the same kind stops at once,
as it would without the recorder.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import math
import signal
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path

import jax
import numpy as np

from kinetix_cli.config import CONFIG_FILENAME, ExperimentConfig, PPOSettings, RunSettings, save_config
from kinetix_cli.constants import EVAL_FORMAT, VERSIONS_FORMAT
from kinetix_cli.env.level import to_host
from kinetix_cli.errors import Stopped, UserError
from kinetix_cli.io import atomic_write_json, atomic_write_text, write_reason
from kinetix_cli.levels.files import level_paths
from kinetix_cli.parallel import is_primary, primary_decides, sync
from kinetix_cli.provenance import environment_info
from kinetix_cli.rl.checkpoints import checkpoint_manager, save_runner, writing
from kinetix_cli.rl.curricula import Curriculum
from kinetix_cli.rl.evaluate import Evaluator, evaluation_record
from kinetix_cli.rl.ppo import Runner

METRICS_FILE = "metrics.jsonl"
CLONE_FILE = "clone.jsonl"
VERSIONS_FILE = "versions.json"
EVALUATIONS = "evaluations"
"""Folder of a run's evaluations during training: `<update>.json`, each as `kinetix eval --json` writes it."""
STOP_SIGNALS = (signal.SIGTERM, signal.SIGINT)
"""The signals that stop a run after the update in flight."""


@dataclasses.dataclass
class Recorder:
    """Records one run (the primary process writes its files; every process writes its checkpoint shards).

    Attributes:
        config: the experiment, saved as the run's `config.yaml` and given to wandb.
        run_dir: the run's folder.
        resume: whether the run continues from `first_update`.
        first_update: 0, or the update of the checkpoint it resumes from.
        curriculum: what the run logs of its curriculum.
        evaluator: plays the parameters on `run.eval_levels` (None: no evaluation during training).
        progress: called with each update's record (the primary process only).
    """

    config: ExperimentConfig
    run_dir: Path
    resume: bool
    first_update: int
    curriculum: Curriculum
    evaluator: Evaluator | None
    progress: Callable[[dict], None] | None = None
    trained: float = 0.0
    """Training time so far [s]: what `run.minutes` counts, compile and behaviour cloning included."""
    solved: float = 0.0
    """Training episodes solved so far (`run.restart_unsolved_after`)."""
    finished: bool = False
    """Whether the last update of the run (its last, its budget's or a stop's) is recorded."""
    kept: int | None = None
    """The last complete checkpoint's update."""
    signalled: int | None = None
    """The first stop signal this process received, if any."""
    stopped: bool = False
    """Whether a stop signal ended the run (the primary process's decides for every process)."""
    _files: tuple = dataclasses.field(default=(), init=False, repr=False)
    """(checkpoint manager, metrics file, wandb run) while the recorder is open."""
    _spent: bool = dataclasses.field(default=False, init=False, repr=False)
    """Whether a resumed run had used up its budget before it started again."""
    _started: float = dataclasses.field(default=0.0, init=False, repr=False)
    """When the update in flight started (`time.perf_counter`)."""

    @property
    def settings(self) -> RunSettings:
        return self.config.run

    @property
    def ppo(self) -> PPOSettings:
        return self.config.ppo

    @property
    def clone_log(self) -> Path | None:
        """Where behaviour cloning before PPO logs its steps (the primary process only)."""
        return self.run_dir / CLONE_FILE if is_primary() else None

    @contextlib.contextmanager
    def open(self) -> Iterator[Recorder]:
        """The recorder, its files open, for the run's updates: the primary process writes the config and versions
        and keeps the metrics up to `first_update`; stop signals are heard while the block runs."""
        sync("checked")  # every process has read the run before the primary writes to it
        primary = is_primary()
        try:
            if primary:
                self.run_dir.mkdir(parents=True, exist_ok=True)
                save_config(self.config, self.run_dir / CONFIG_FILENAME)
                atomic_write_json(self.run_dir / VERSIONS_FILE, environment_info(), VERSIONS_FORMAT)
                _truncate_metrics(self.run_dir / METRICS_FILE, self.first_update)  # keep what it will not redo
            sync("prepared")
            manager = checkpoint_manager(self.run_dir)
            logger = _wandb_run(self.config, self.run_dir, self.resume) if primary else None
            log = open(self.run_dir / METRICS_FILE, "a") if primary else contextlib.nullcontext()  # noqa: SIM115
        except OSError as exc:
            raise UserError(f"--run-dir {self.run_dir}: cannot write: {exc.strerror or exc}") from None
        self.kept = self.first_update or None
        if self.first_update and primary:
            self.trained = _trained_seconds(self.run_dir / METRICS_FILE, self.ppo) + self.cloned_seconds()
            self.solved = _solved_episodes(self.run_dir / METRICS_FILE)
        budget = self.settings.minutes * 60  # 0: none; the primary's clock decides for every process
        self._spent = bool(budget) and primary_decides("budget", self.trained >= budget)  # a resumed run used it up
        self._files = (manager, log, logger)
        with log, writing(manager), self._hearing_stops():
            yield self
        if logger is not None:
            logger.finish()
        if self.stopped:
            signum = self.signalled or signal.SIGTERM  # a process the primary's signal stopped
            raise Stopped(
                f"stopped by {signal.Signals(signum).name} after update {self.kept}: checkpoint {self.kept} is saved; "
                "rerun with --resume to continue from it",
                signum,
            )

    def cloned_seconds(self) -> float:
        """Time of the behaviour-cloning steps before PPO logged in the run's `clone.jsonl` [s] (0 without)."""
        return sum(record["seconds"] for record in _logged(self.run_dir / CLONE_FILE))

    def updates(self) -> Iterator[int]:
        """The updates (0-based) the run has left, each timed from here until `measure`; none when a resumed run
        had used up its budget; ends after the update `record` finds last."""
        for update in range(self.first_update, self.first_update if self._spent else self.ppo.num_updates):
            self._started = time.perf_counter()
            yield update
            if self.finished:
                return

    def measure(self, update: int, runner: Runner, metrics: dict, logged: dict) -> dict:
        """The record of update `update` (0-based) from its metrics (device scalars) and what the run logs beside
        them (`logged`: the pool's round); counts its time and solved episodes. Non-finite metrics end the run
        with one line."""
        metrics = self.curriculum.logged({k: float(v) for k, v in jax.device_get(metrics).items()})
        seconds = time.perf_counter() - self._started
        steps = (update + 1) * self.ppo.batch_size
        record = {"update": update + 1, "steps": steps, "sps": self.ppo.batch_size / seconds} | metrics
        record |= self.curriculum.metrics(runner, steps) | logged
        if not all(math.isfinite(v) for v in metrics.values()):
            bad = sorted(k for k, v in metrics.items() if not math.isfinite(v))
            raise UserError(
                f"{self.run_dir}: update {update + 1}: {', '.join(bad)} not finite: training diverged (ppo.lr "
                f"{self.ppo.lr:g}, max_grad_norm {self.ppo.max_grad_norm:g}); nothing of this update was kept"
            )
        self.trained += seconds
        self.solved += metrics["solve_rate"] * metrics["episodes"]
        return record

    def record(self, runner: Runner, record: dict) -> None:
        """Evaluate (every `run.eval_every` updates and after the last), log and checkpoint (every
        `run.checkpoint_every` updates and after the last or a stop) the update of `record`; decides whether the
        run ends with it: its last update, the end of its budget, or a stop signal."""
        update, budget = record["update"], self.settings.minutes * 60
        out_of_time = bool(budget) and primary_decides("budget", self.trained >= budget)
        last = update == self.ppo.num_updates or out_of_time
        self.stopped = primary_decides("stop", self.signalled is not None) and not last
        self.finished = last or self.stopped
        evaluation = None  # a stopped run evaluates where an uninterrupted one does: its resume does the rest
        if self.evaluator is not None and (update % self.settings.eval_every == 0 or last):
            evaluation = _evaluation(self.evaluator, runner.params, self.settings, self.run_dir, update)
            record |= _evaluation_metrics(evaluation)
        manager, log, logger = self._files
        try:
            if is_primary():
                if evaluation is not None:
                    atomic_write_json(self.run_dir / EVALUATIONS / f"{update}.json", evaluation, EVAL_FORMAT)
                log.write(json.dumps(record) + "\n")
                log.flush()
            every = self.settings.checkpoint_every
            if (every and update % every == 0) or self.finished:
                save_runner(manager, update, runner)
                self.kept = update
        except (OSError, UserError, ValueError) as exc:  # orbax reports a failed write as a ValueError
            raise _write_failed(self.run_dir, update, exc, self.kept) from None
        if logger is not None:
            logger.log(record, step=record["steps"])
        if self.progress is not None and is_primary():
            self.progress(record)

    @contextlib.contextmanager
    def _hearing_stops(self) -> Iterator[None]:
        """While the block runs, the first SIGTERM or SIGINT only asks the run to stop after the update in flight;
        the signal's own handler is back from then on, so a second one acts at once. Signals can only be handled
        in the main thread: elsewhere (a run in a worker thread) they keep their handlers."""
        if threading.current_thread() is not threading.main_thread():
            yield
            return
        before = {signum: signal.getsignal(signum) for signum in STOP_SIGNALS}

        def hear(signum, frame):
            if self.signalled is None:
                self.signalled = signum
            signal.signal(signum, before[signum])

        for signum in STOP_SIGNALS:
            signal.signal(signum, hear)
        try:
            yield
        finally:
            for signum, handler in before.items():
                signal.signal(signum, handler)


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


def evaluator(config: ExperimentConfig, devices: int | None) -> Evaluator | None:
    """The evaluator of `run.eval_levels` (loaded once; each process evaluates on its `devices` local devices),
    or None when training does not evaluate."""
    if not (config.run.eval_every and config.run.eval_levels):
        return None
    return Evaluator(config, level_paths(config.run.eval_levels), config.run.eval_attempts, devices)


def _evaluation(evaluator: Evaluator, params, run: RunSettings, run_dir: Path, update: int) -> dict:
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


def _trained_seconds(path: Path, settings: PPOSettings) -> float:
    """Training time of the updates logged in `metrics.jsonl` [s], rebuilt from each one's steps per second (what
    `run.minutes` counts, the first update's compile included; a resumed run goes on from it)."""
    return sum(settings.batch_size / record["sps"] for record in _logged(path))


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
