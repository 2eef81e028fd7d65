"""Learning curves from run directories (`kinetix plot`): read each run's `metrics.jsonl` and resolved config,
group runs that differ only in their seed, and draw each group's mean with its spread over seeds.

A run still training can be read: a torn last line of `metrics.jsonl` is skipped with a warning. The x axis is
environment steps, or training time rebuilt from each update's steps per second (`sps`: the first update's
includes its compile; evaluations are not counted).
"""

from __future__ import annotations

import dataclasses
import json
import warnings
from pathlib import Path

import numpy as np
import yaml

from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_write

METRICS_FILE = "metrics.jsonl"
CONFIG_FILE = "config.yaml"
X_AXES = ("steps", "time")
SEED_KEY = "run.seed"
IGNORED_KEYS = (SEED_KEY, "run.wandb", "ppo.total_timesteps", "run.checkpoint_every", "run.eval_every")
"""Settings that do not make runs different experiments: curves of runs that differ only here are one group."""
MAX_LABEL_KEYS = 3
"""Groups that differ in more settings than this are labelled by a run's folder name instead."""


@dataclasses.dataclass(frozen=True)
class Run:
    """One run directory: its flattened config (`section.key` -> value) and its metrics, one dict per line."""

    path: Path
    settings: dict
    lines: list[dict]


@dataclasses.dataclass(frozen=True)
class Curve:
    """One group's curve of one metric: x (n,), the mean over its runs (n,) and the band (min, max over runs)."""

    metric: str
    label: str
    runs: tuple[Path, ...]
    x: np.ndarray
    mean: np.ndarray
    low: np.ndarray
    high: np.ndarray

    def rows(self) -> list[dict]:
        """The plotted numbers, one dict per point."""
        return [
            {"metric": self.metric, "group": self.label, "runs": len(self.runs), "x": float(x), "mean": float(m),
             "min": float(lo), "max": float(hi)}
            for x, m, lo, hi in zip(self.x, self.mean, self.low, self.high, strict=True)
        ]  # fmt: skip


def read_run(path: Path) -> Run:
    """A run directory's config and metrics; one clear error if `path` is not a run."""
    metrics, config = path / METRICS_FILE, path / CONFIG_FILE
    if not path.is_dir() or not metrics.is_file() or not config.is_file():
        raise UserError(f"{path}: not a run directory (needs {METRICS_FILE} and {CONFIG_FILE})")
    try:
        settings = _flatten(yaml.safe_load(config.read_text(encoding="utf-8")) or {})
        text = metrics.read_text(encoding="utf-8")
    except (UnicodeDecodeError, yaml.YAMLError) as exc:
        raise UserError(f"{path}: unreadable run files ({type(exc).__name__})") from None
    lines = []
    rows = text.splitlines()
    for number, row in enumerate(rows, 1):
        try:
            lines.append(json.loads(row))
        except json.JSONDecodeError:
            if number == len(rows):  # the line a running run is writing
                warnings.warn(f"{metrics}: line {number} is incomplete (a run still writing?); skipped", stacklevel=2)
                continue
            raise UserError(f"{metrics}: line {number} is not JSON") from None
    return Run(path, settings, lines)


def _flatten(tree: dict, prefix: str = "") -> dict:
    flat = {}
    for key, value in tree.items():
        if isinstance(value, dict):
            flat |= _flatten(value, f"{prefix}{key}.")
        else:
            flat[f"{prefix}{key}"] = value
    return flat


def group_runs(runs: list[Run], by: list[str] | None = None) -> dict[str, list[Run]]:
    """Runs grouped into experiments, each labelled by what sets it apart. Without `by`, runs whose settings
    differ only in `IGNORED_KEYS` (seed, budget, logging) are one group, labelled by the settings that differ
    between groups (by a run's folder name when more than `MAX_LABEL_KEYS` differ); with `by` (config keys),
    runs are grouped by those keys' values."""
    known = set().union(*(run.settings for run in runs))
    for key in by or []:
        if key not in known:
            raise UserError(f"--group: unknown config key {key!r} (e.g. curriculum.name, ppo.lr, model.name)")

    def identity(run: Run) -> tuple:
        keys = by or sorted(k for k in known if k not in IGNORED_KEYS)
        return tuple((k, json.dumps(run.settings.get(k), sort_keys=True)) for k in keys)

    groups: dict[tuple, list[Run]] = {}
    for run in runs:
        groups.setdefault(identity(run), []).append(run)
    differing = [k for k in (by or sorted(known - set(IGNORED_KEYS))) if len({dict(g)[k] for g in groups}) > 1]
    labels = {}
    for key, members in groups.items():
        values = dict(key)
        named = 0 < len(differing) <= MAX_LABEL_KEYS
        label = ", ".join(f"{k}={_shown(json.loads(values[k]))}" for k in differing) if named else members[0].path.name
        labels[label] = members
    return labels


def _shown(value) -> str:
    """A setting's value as a label shows it: YAML's null as `none` (as in `--from none`)."""
    return "none" if value is None else str(value)


def curve(metric: str, label: str, runs: list[Run], x_axis: str = "steps") -> Curve:
    """The curve of `metric` over the group `runs`: mean and min..max over runs at each x where every run has
    a value (runs still training: up to the shortest)."""
    if x_axis not in X_AXES:
        raise UserError(f"--x: unknown axis {x_axis!r}; choose one of {', '.join(X_AXES)}")
    series = [_series(run, metric, x_axis) for run in runs]
    n = min(len(xs) for xs, _ in series)
    xs = np.mean([xs[:n] for xs, _ in series], axis=0)
    ys = np.array([ys[:n] for _, ys in series]).reshape(len(series), n)
    return Curve(metric, label, tuple(r.path for r in runs), xs, ys.mean(0), ys.min(0), ys.max(0))


def _series(run: Run, metric: str, x_axis: str) -> tuple[np.ndarray, np.ndarray]:
    steps = np.array([line.get("total_steps", line.get("steps", 0)) for line in run.lines], float)
    if x_axis == "time":
        deltas = np.diff(np.concatenate([[0.0], [line.get("steps", 0) for line in run.lines]]))
        sps = np.array([line.get("sps") or np.nan for line in run.lines], float)
        steps = np.nancumsum(deltas / sps)
    rows = [i for i, line in enumerate(run.lines) if isinstance(line.get(metric), int | float)]
    return steps[rows], np.array([run.lines[i][metric] for i in rows], float)


def metrics_of(runs: list[Run]) -> set[str]:
    """Every numeric metric some run logged."""
    return {k for run in runs for line in run.lines for k, v in line.items() if isinstance(v, int | float)}


def learning_curves(
    paths: list[Path], metrics: list[str], x_axis: str = "steps", by: list[str] | None = None
) -> list[Curve]:
    """One curve per metric and group of runs (see `group_runs`), metric by metric."""
    runs = [read_run(Path(p)) for p in paths]
    known = metrics_of(runs)
    for metric in metrics:
        if metric not in known:
            raise UserError(f"--metric: no run logged {metric!r}; these did: {', '.join(sorted(known))}")
    groups = group_runs(runs, by)
    return [curve(metric, label, members, x_axis) for metric in metrics for label, members in groups.items()]


def draw(curves: list[Curve], x_axis: str = "steps"):
    """A matplotlib figure: one panel per metric, one line per group with its band (min..max over its runs)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import EngFormatter

    metrics = list(dict.fromkeys(c.metric for c in curves))
    fig, axes = plt.subplots(1, len(metrics), figsize=(5 * len(metrics), 3.6), squeeze=False)
    for ax, metric in zip(axes[0], metrics, strict=True):
        for c in (c for c in curves if c.metric == metric):
            label = f"{c.label} ({len(c.runs)} runs)" if len(c.runs) > 1 else c.label
            (line,) = ax.plot(c.x, c.mean, label=label)
            if len(c.runs) > 1:
                ax.fill_between(c.x, c.low, c.high, color=line.get_color(), alpha=0.2, linewidth=0)
        ax.set_title(metric)
        ax.set_xlabel("environment steps" if x_axis == "steps" else "training time [s]")
        ax.xaxis.set_major_formatter(EngFormatter(sep=""))  # 200k, 1.5M: no overlapping long numbers
        if "solve" in metric:  # a rate: always the whole 0..1 range
            ax.set_ylim(-0.03, 1.03)
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize="small")
    fig.tight_layout()
    return fig


def save_figure(figure, path: Path) -> None:
    """Write a matplotlib figure atomically, in the type its file name ends with (png, svg, pdf)."""
    import matplotlib.pyplot as plt

    atomic_write(path, lambda f: figure.savefig(f, format=path.suffix.lower()[1:], dpi=120))
    plt.close(figure)
