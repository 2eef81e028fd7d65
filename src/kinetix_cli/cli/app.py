"""The `kinetix` application: every command group registered on one typer app, and `main`, which turns a
`UserError` into one line on stderr and exit code 2."""

from __future__ import annotations

import atexit
import gc
import sys
import warnings

import typer
from rich.table import Table

from kinetix_cli import compile_cache, cpu, trace_cache
from kinetix_cli.cli import figures, generate, levels, studio, train
from kinetix_cli.cli.agents import agents_app
from kinetix_cli.cli.bench import bench_app
from kinetix_cli.cli.console import console, say, show_warning
from kinetix_cli.cli.validation import validation_app
from kinetix_cli.errors import Stopped, UserError

app = typer.Typer(no_args_is_help=True, add_completion=False, help="kinetix: open-ended 2D physics RL in JAX.")
app.add_typer(levels.commands)
app.add_typer(generate.commands)
app.add_typer(train.commands)
app.add_typer(figures.commands)
app.add_typer(studio.commands)
app.add_typer(levels.levels_app, name="levels")
app.add_typer(bench_app, name="bench")
app.add_typer(agents_app, name="agents")
app.add_typer(validation_app, name="validation")


@app.command()
def demo(seconds: float = typer.Option(4.0, min=0.5, help="Simulated seconds.")) -> None:
    """A car drives up a ramp: build a scene, simulate it, print what happened."""
    from kinetix_cli.tools.demo import run_demo

    say(("kinetix demo", "bold"), ": a two-wheeled car drives right, up a ramp (engine size m, CPU).")
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
    """Entry point: run the app; user errors print one line and exit with code 2; a training run stopped by a
    signal prints one line and exits with 128 + the signal's number.

    Compiled programs are cached on disk (`kinetix_cli.compile_cache`: `~/.cache/kinetix/jax/<versions>`;
    `KINETIX_COMPILE_CACHE=DIR` or `off`), so a command run again skips XLA's compile of what it ran before, and
    the big programs' traces with them (`kinetix_cli.trace_cache`, in that folder's `traces`). The CPU
    is split into one JAX device per core (`kinetix_cli.cpu`: at most 4; `KINETIX_CPU_DEVICES=N`).
    """
    try:
        _run()
    finally:
        # The command is over. Python's exit would walk the whole heap once more for cycles (a training run's
        # traces and programs: 0.3-0.8 s) just before the process's end frees it all; frozen, the walk is skipped.
        # Registered last, it runs first: before jax's exit handler, whose clearing of caches starts such a walk.
        atexit.unregister(gc.freeze)
        atexit.register(gc.freeze)


def _run() -> None:
    """`main` until the command is over."""
    folder = compile_cache.cache_folder()
    compile_cache.enable(folder)
    trace_cache.enable(trace_cache.folder_in(folder))
    warnings.showwarning = show_warning
    sys.unraisablehook = _quiet_closed_event_loops
    try:
        cpu.split()
        code = app(standalone_mode=False)
    except UserError as exc:
        say(("error:", "red"), f" {exc}", stderr=True)
        sys.exit(exc.exit_code)
    except Stopped as exc:  # a training run told to stop by a signal, checkpointed
        say(str(exc), stderr=True)
        sys.exit(exc.exit_code)
    except typer.Abort:  # Ctrl-C
        say("aborted", stderr=True)
        sys.exit(130)
    except Exception as exc:
        if not _is_usage_error(exc):
            raise
        if type(exc).__name__ == "NoArgsIsHelpError":  # a group without a command: its help, as --help prints it
            console.print(exc.format_message())
        else:  # a bad flag or argument: one line too (typer would draw a multi-line box)
            where = f"{exc.ctx.command_path}: " if exc.ctx is not None else ""
            say(("error:", "red"), f" {where}{exc.format_message()} (see --help)", stderr=True)
        sys.exit(2)
    sys.exit(code if isinstance(code, int) else 0)


def _quiet_closed_event_loops(unraisable) -> None:
    """Drop the "Event loop is closed" callbacks orbax's async readers leave behind when a damaged checkpoint
    fails to load (the user has already read the one error line); report anything else as Python would."""
    if isinstance(unraisable.exc_value, RuntimeError) and "Event loop is closed" in str(unraisable.exc_value):
        return
    sys.__unraisablehook__(unraisable)


def _is_usage_error(exc: Exception) -> bool:
    """A click usage error (typer vendors its own click, so the class is recognised by its interface)."""
    return hasattr(exc, "format_message") and hasattr(exc, "ctx") and getattr(exc, "exit_code", None) == 2
