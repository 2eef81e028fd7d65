"""Evaluations side by side (`kinetix compare`): the solve rate of every level and suite in several
`kinetix eval --json` files (DR vs SFL, fine-tuned vs from scratch, ...), and the difference of the last from the
first, as a table or a grouped bar chart."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from kinetix_cli.errors import UserError
from kinetix_cli.rl import evaluate


@dataclasses.dataclass(frozen=True)
class Evaluation:
    """One eval file: its label and the solve rate of each level and each suite (in file order)."""

    path: Path
    levels: dict[str, float]
    suites: dict[str, float]


@dataclasses.dataclass(frozen=True)
class Row:
    """One level or suite across the evaluations: solve rates (None where an evaluation lacks it) and the last
    minus the first (None unless both have it)."""

    kind: str
    name: str
    rates: tuple[float | None, ...]

    @property
    def difference(self) -> float | None:
        first, last = self.rates[0], self.rates[-1]
        return None if first is None or last is None else last - first


def read_evaluation(path: Path) -> Evaluation:
    """An eval file's solve rates; another format or a malformed file is one error naming the file and field."""
    record = evaluate.read_evaluation(path)
    return Evaluation(
        path,
        {str(e["level"]): float(e["solve_rate"]) for e in record["levels"]},
        {str(name): float(suite["solve_rate"]) for name, suite in record["suites"].items()},
    )


def labels(evaluations: list[Evaluation]) -> list[str]:
    """Short names for the columns: file names; where two are alike, their folders (a run's eval file is named by
    its run), or folder/file if those are alike too."""
    stems = [e.path.stem for e in evaluations]
    names = [e.path.parent.name if stems.count(stem) > 1 else stem for e, stem in zip(evaluations, stems, strict=True)]
    if len(set(names)) < len(names):
        names = [f"{e.path.parent.name}/{e.path.stem}" for e in evaluations]
    return names


def compare(paths: list[Path]) -> tuple[list[str], list[Row]]:
    """The column labels and one row per level (first-seen order), then one per suite."""
    if len(paths) < 2:
        raise UserError("compare: give two or more eval files (kinetix eval RUN --levels ... --json FILE)")
    evaluations = [read_evaluation(Path(p)) for p in paths]
    rows = []
    for kind, field in (("level", "levels"), ("suite", "suites")):
        names = dict.fromkeys(name for e in evaluations for name in getattr(e, field))
        rows += [Row(kind, name, tuple(getattr(e, field).get(name) for e in evaluations)) for name in names]
    return labels(evaluations), rows


def markdown(columns: list[str], rows: list[Row]) -> str:
    """A Markdown table: solve rates in percent, the difference in points."""
    percent = lambda r: "-" if r is None else f"{100 * r:.1f}%"  # noqa: E731
    header = ["level / suite", *columns, f"{columns[-1]} - {columns[0]}"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in rows:
        name = f"**{row.name}** (mean)" if row.kind == "suite" else row.name
        diff = "-" if row.difference is None else f"{100 * row.difference:+.1f}"
        lines.append("| " + " | ".join([name, *map(percent, row.rates), diff]) + " |")
    return "\n".join(lines) + "\n"


def draw(columns: list[str], rows: list[Row]):
    """A grouped bar chart: one group per level and suite, one bar per evaluation."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    width = 0.8 / len(columns)
    fig, ax = plt.subplots(figsize=(min(16.0, max(6.0, 2.0 + 0.2 * len(rows) * len(columns))), 4.0))
    x = np.arange(len(rows))
    for i, column in enumerate(columns):
        rates = [np.nan if r.rates[i] is None else r.rates[i] for r in rows]
        ax.bar(x + (i - (len(columns) - 1) / 2) * width, rates, width, label=column)
    ax.set_xticks(x, [Path(r.name).stem if r.kind == "level" else f"{r.name} (mean)" for r in rows])
    ax.tick_params(axis="x", labelrotation=60, labelsize="small")
    ax.set_ylabel("solve rate")
    ax.set_ylim(0, 1)
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.0, 1.0))  # beside the bars, never on them
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig
