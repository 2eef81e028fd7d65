"""The `kinetix` command line. Each command builds a config and calls one library function."""

from __future__ import annotations

import sys
from pathlib import Path

import typer
from rich.console import Console
from rich.table import Table

from kinetix_cli.errors import UserError

app = typer.Typer(no_args_is_help=True, add_completion=False, help="kinetix: open-ended 2D physics RL in JAX.")
bench_app = typer.Typer(no_args_is_help=True, help="Benchmarks: compile time and steady-state throughput.")
app.add_typer(bench_app, name="bench")
console = Console()


def _int_list(flag: str, text: str) -> tuple[int, ...]:
    try:
        values = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise UserError(f"{flag}: expected comma-separated integers, got {text!r}") from None
    if not values or any(v < 1 for v in values):
        raise UserError(f"{flag}: expected positive integers, got {text!r}")
    return values


@bench_app.command("engine")
def bench_engine_command(
    size: str = typer.Option("s", help="Scene size: s, m or l."),
    envs: str = typer.Option("1,64,1024,4096", help="Comma-separated batch sizes."),
    against: str = typer.Option(None, help="Also run the reference engine on the same scenes: jax2d."),
    steps: int = typer.Option(20, min=1, help="Engine steps per timed call."),
    min_time: float = typer.Option(2.0, min=0.0, help="Seconds of timed calls per measurement."),
    seed: int = typer.Option(0, help="Seed of the random scenes and actions."),
    json_path: Path = typer.Option(None, "--json", help="Also write the results to this JSON file."),
) -> None:
    """Engine steps per second on random scenes filled to a size's capacity."""
    from kinetix_cli.bench import BENCH_FORMAT, EngineBenchConfig, bench_engine, environment_info
    from kinetix_cli.io import atomic_write_json

    config = EngineBenchConfig(
        size=size, envs=_int_list("--envs", envs), against=against, steps=steps, min_time=min_time, seed=seed
    )
    table = Table("engine", "size", "envs", "compile [s]", "steps/s", "vs jax2d")
    ours: dict[int, float] = {}

    def report(r):
        if r.engine == "kinetix":
            ours[r.envs] = r.steps_per_s
        ratio = f"{ours[r.envs] / r.steps_per_s:.1f}x" if r.engine == "jax2d" else ""
        console.print(
            f"[dim]{r.engine:8s} size {r.size} envs {r.envs:5d}: compile {r.compile_s:6.1f} s, "
            f"{r.steps_per_s:12,.0f} steps/s {ratio}[/dim]"
        )
        table.add_row(r.engine, r.size, str(r.envs), f"{r.compile_s:.1f}", f"{r.steps_per_s:,.0f}", ratio)

    results = bench_engine(config, report)
    console.print(table)
    if json_path is not None:
        import dataclasses

        payload = {
            **environment_info(),
            "config": dataclasses.asdict(config),
            "results": [dataclasses.asdict(r) for r in results],
        }
        atomic_write_json(json_path, payload, BENCH_FORMAT)
        console.print(f"wrote {json_path}")


@app.command()
def demo(seconds: float = typer.Option(4.0, min=0.5, help="Simulated seconds.")) -> None:
    """A car drives up a ramp: build a scene, simulate it, print what happened."""
    from kinetix_cli.demo import run_demo

    console.print("[bold]kinetix demo[/bold]: a two-wheeled car drives right, up a ramp (engine size m, CPU).")
    frames, compile_s, rate = run_demo(seconds)
    table = Table("t [s]", "x [m]", "y [m]", "angle [deg]", "speed [m/s]", title="chassis")
    for f in frames:
        table.add_row(f"{f.t:.2f}", f"{f.x:.2f}", f"{f.y:.2f}", f"{f.angle_deg:.1f}", f"{f.speed:.2f}")
    console.print(table)
    start, end = frames[0], frames[-1]
    peak = max(frames, key=lambda f: f.y)
    console.print(f"compile {compile_s:.1f} s; simulated {end.t:.1f} s at {rate:,.0f} engine steps/s (1 scene).")
    console.print(
        f"the car drove {end.x - start.x:+.2f} m right and climbed the ramp to {peak.y - start.y:+.2f} m "
        f"(t = {peak.t:.1f} s, tilted {peak.angle_deg:.0f} deg)."
    )


def main() -> None:
    """Entry point: run the app; user errors print one line and exit with code 2."""
    try:
        app()
    except UserError as exc:
        Console(stderr=True).print(f"[red]error:[/red] {exc}", highlight=False)
        sys.exit(exc.exit_code)
