"""`kinetix plot`: learning curves of runs (figures for a person, numbers for a program)."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import typer

from kinetix_cli.cli.console import say

commands = typer.Typer()

PLOT_FORMAT = "kinetix-curves/1"


def _split(text: str | None) -> list[str]:
    return [item.strip() for item in (text or "").split(",") if item.strip()]


@commands.command()
def plot(
    runs: list[Path] = typer.Argument(..., help="Run directories (pretrain or finetune; still training is fine)."),
    output: Path = typer.Option(None, "-o", "--output", help="Figure file (PNG, SVG or PDF)."),
    metric: str = typer.Option("eval_solve_rate,solve_rate,return", "--metric", help="Comma-separated metrics."),
    x: str = typer.Option("steps", "--x", help="x axis: steps (environment steps) or time (training seconds)."),
    group: str = typer.Option(
        None, "--group", help="Comma-separated config keys to group runs by (default: runs differing only in seed)."
    ),
    json_out: Path = typer.Option(None, "--json", help="Also write the plotted numbers as JSON."),
    csv_out: Path = typer.Option(None, "--csv", help="Also write the plotted numbers as CSV."),
) -> None:
    """Learning curves of runs: one panel per metric, one line per group of runs with the spread over its seeds
    (min to max, shaded). Runs that differ only in their seed form one group; the legend names what differs."""
    from kinetix_cli.errors import UserError
    from kinetix_cli.io import atomic_write, atomic_write_json, atomic_write_text, check_output_file
    from kinetix_cli.viz.curves import draw, learning_curves

    if output is None and json_out is None and csv_out is None:
        raise UserError("plot: give -o FIGURE, --json FILE or --csv FILE")
    outputs = [(output, "-o"), (json_out, "--json"), (csv_out, "--csv")]
    for path, flag in outputs:
        if path is not None:
            check_output_file(path, flag)
    if output is not None and output.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise UserError(f"-o {output}: unknown figure type {output.suffix!r}; use .png, .svg or .pdf")
    curves = learning_curves(runs, _split(metric) or ["solve_rate"], x, _split(group) or None)
    rows = [row for c in curves for row in c.rows()]
    if output is not None:
        figure = draw(curves, x)
        atomic_write(output, lambda f: figure.savefig(f, format=output.suffix.lower()[1:], dpi=120))
        say(f"wrote {output} ({len(curves)} curves)")
    if json_out is not None:
        atomic_write_json(json_out, {"x": x, "points": rows}, PLOT_FORMAT)
        say(f"wrote {json_out}")
    if csv_out is not None:
        text = io.StringIO()
        writer = csv.DictWriter(text, fieldnames=["metric", "group", "runs", "x", "mean", "min", "max"])
        writer.writeheader()
        writer.writerows(rows)
        atomic_write_text(csv_out, text.getvalue())
        say(f"wrote {csv_out}")
