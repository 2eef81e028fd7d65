"""`kinetix plot` and `kinetix compare`: learning curves of runs and evaluations side by side (figures for a
person, numbers for a program)."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import typer

from kinetix_cli.cli.console import name_list, say
from kinetix_cli.constants import COMPARE_FORMAT, CURVES_FORMAT

commands = typer.Typer()


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
    from kinetix_cli.io import atomic_write_json, atomic_write_text
    from kinetix_cli.viz.curves import draw, learning_curves, save_figure

    if output is None and json_out is None and csv_out is None:
        raise UserError("plot: give -o FIGURE, --json FILE or --csv FILE")
    _check_outputs(output, [(json_out, "--json"), (csv_out, "--csv")])
    curves = learning_curves(runs, list(name_list(metric)) or ["solve_rate"], x, list(name_list(group or "")) or None)
    rows = [row for c in curves for row in c.rows()]
    if output is not None:
        save_figure(draw(curves, x), output)
        say(f"wrote {output} ({len(curves)} curves)")
    if json_out is not None:
        atomic_write_json(json_out, {"x": x, "points": rows}, CURVES_FORMAT)
        say(f"wrote {json_out}")
    if csv_out is not None:
        text = io.StringIO()
        writer = csv.DictWriter(text, fieldnames=["metric", "group", "runs", "x", "mean", "min", "max"])
        writer.writeheader()
        writer.writerows(rows)
        atomic_write_text(csv_out, text.getvalue())
        say(f"wrote {csv_out}")


@commands.command()
def compare(
    files: list[Path] = typer.Argument(..., help="Two or more `kinetix eval --json` files."),
    as_markdown: bool = typer.Option(False, "--markdown", help="Print a Markdown table instead of a terminal table."),
    output: Path = typer.Option(None, "-o", "--output", help="Also draw a bar chart (PNG, SVG or PDF)."),
    json_out: Path = typer.Option(None, "--json", help="Also write the table as JSON."),
) -> None:
    """Solve rates per level and per suite of several evaluations side by side (DR vs SFL, fine-tuned vs from
    scratch, ...), with the difference of the last from the first."""
    from rich.table import Table

    from kinetix_cli.cli.console import console
    from kinetix_cli.io import atomic_write_json
    from kinetix_cli.viz.compare import compare as compare_files
    from kinetix_cli.viz.compare import draw, markdown
    from kinetix_cli.viz.curves import save_figure

    _check_outputs(output, [(json_out, "--json")])
    columns, rows = compare_files(files)
    if as_markdown:
        print(markdown(columns, rows), end="")
    else:
        table = Table("level / suite", *columns, f"{columns[-1]} - {columns[0]}")
        for row in rows:
            rates = ["-" if r is None else f"{100 * r:.1f}%" for r in row.rates]
            diff = "-" if row.difference is None else f"{100 * row.difference:+.1f}"
            table.add_row(row.name if row.kind == "level" else f"{row.name} (mean)", *rates, diff)
        console.print(table)
    if output is not None:
        save_figure(draw(columns, rows), output)
        say(f"wrote {output}")
    if json_out is not None:
        table_rows = [
            {"kind": r.kind, "name": r.name, "solve_rates": dict(zip(columns, r.rates, strict=True)),
             "difference": r.difference}
            for r in rows
        ]  # fmt: skip
        atomic_write_json(json_out, {"files": [str(f) for f in files], "rows": table_rows}, COMPARE_FORMAT)
        say(f"wrote {json_out}")


FIGURE_TYPES = (".png", ".svg", ".pdf")


def _check_outputs(figure: Path | None, others: list[tuple[Path | None, str]]) -> None:
    """Before any work: every output given is writable, and the figure (-o) of a type matplotlib writes."""
    from kinetix_cli.errors import UserError
    from kinetix_cli.io import check_output_file

    for path, flag in [(figure, "-o"), *others]:
        if path is not None:
            check_output_file(path, flag)
    if figure is not None and figure.suffix.lower() not in FIGURE_TYPES:
        raise UserError(f"-o {figure}: unknown figure type {figure.suffix!r}; use .png, .svg or .pdf")


@commands.command()
def report(
    runs: list[Path] = typer.Argument(..., help="Run directories (pretrain or finetune; several seeds are grouped)."),
    out: Path = typer.Option(..., "-o", "--out", help="Report folder to write (index.html and its images)."),
    group: str = typer.Option(
        None, "--group", help="Comma-separated config keys to group runs by (default: runs differing only in seed)."
    ),
    evaluation: list[Path] = typer.Option(
        [], "--eval", help="A kinetix eval --json file per run, in run order, instead of each run's latest."
    ),
    gifs: bool = typer.Option(True, "--gifs/--no-gifs", help="Play each evaluated level for a GIF of the agent."),
) -> None:
    """A static page of runs (DIR/index.html, opens from disk in any browser): learning curves, the latest
    evaluation with each level's picture and a GIF of the agent, the curriculum buffer's top levels, the resolved
    config and the library versions; report.json holds its numbers."""
    from kinetix_cli.viz.report import write_report

    payload = write_report(
        runs,
        out,
        group_by=list(name_list(group or "")) or None,
        evaluations=evaluation or None,
        gifs=gifs,
        progress=say,
    )
    for note in payload["notes"]:
        say(("note: ", "yellow"), note)
    say(f"wrote {out / 'index.html'} ({len(payload['levels'])} levels, {len(payload['runs'])} runs)")
