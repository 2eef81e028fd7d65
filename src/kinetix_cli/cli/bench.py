"""The `kinetix bench` commands: compile time and steady-state throughput of the engine, the environment, PPO
training and level generation. Each builds a config and calls one function of `kinetix_cli.bench`."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Column, Table

from kinetix_cli.cli.console import console, int_list, name_list
from kinetix_cli.constants import INT32_MAX
from kinetix_cli.errors import UserError
from kinetix_cli.io import check_output_file

bench_app = typer.Typer(no_args_is_help=True, help="Benchmarks: compile time and steady-state throughput.")
SCORING = {"score_levels": 384, "score_attempts": 2, "score_steps": 256, "refresh_every": 64}
"""The SFL scoring `bench train --breakdown` times by default: the general recipe's (`experiments/general.yaml`)."""


@bench_app.command("engine")
def bench_engine_command(
    size: str = typer.Option("s", help="Scene size: s, m or l."),
    envs: str = typer.Option("1,64,1024,4096", help="Comma-separated batch sizes."),
    against: str = typer.Option(None, help="Also run the reference engine on the same scenes: jax2d."),
    steps: int = typer.Option(20, min=1, max=10**5, help="Engine steps per timed call."),
    min_time: float = typer.Option(2.0, min=0.0, max=3600.0, help="Seconds of timed calls per measurement."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Seed of the random scenes and actions."),
    json_path: Path = typer.Option(None, "--json", help="Also write the results to this JSON file."),
) -> None:
    """Engine steps per second on random scenes filled to a size's capacity."""
    if json_path is not None:
        check_output_file(json_path, "--json")
    from kinetix_cli.bench.engine import EngineBenchConfig, bench_engine

    config = EngineBenchConfig(
        size=size, envs=int_list("--envs", envs), against=against, steps=steps, min_time=min_time, seed=seed
    )
    table = Table("engine", "size", "envs", "compile [s]", "steps/s", "vs jax2d")
    ours: dict[int, float] = {}

    def report(r):
        if r.engine == "kinetix":
            ours[r.envs] = r.steps_per_s
        ratio = f"{ours[r.envs] / r.steps_per_s:.1f}x" if r.engine == "jax2d" else ""
        console.print(
            f"{r.engine:8s} size {r.size} envs {r.envs:5d}: compile {r.compile_s:6.1f} s, "
            f"{r.steps_per_s:12,.0f} steps/s {ratio}",
            style="dim",
        )
        table.add_row(r.engine, r.size, str(r.envs), f"{r.compile_s:.1f}", f"{r.steps_per_s:,.0f}", ratio)

    results = bench_engine(config, report)
    console.print(table)
    _write_bench_json(json_path, config, results)


@bench_app.command("env")
def bench_env_command(
    size: str = typer.Option("s", help="Level size: s, m or l."),
    envs: str = typer.Option("64,1024", help="Comma-separated batch sizes."),
    obs: str = typer.Option("symbolic-flat,symbolic-entity,pixels", help="Observation types to measure."),
    steps: int = typer.Option(32, min=1, max=10**5, help="Environment steps per timed call."),
    min_time: float = typer.Option(2.0, min=0.0, max=3600.0, help="Seconds of timed calls per measurement."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Seed of the random levels and actions."),
    json_path: Path = typer.Option(None, "--json", help="Also write the results to this JSON file."),
) -> None:
    """Environment steps per second (frame skip, reward, observation and auto-reset included)."""
    if json_path is not None:
        check_output_file(json_path, "--json")
    from kinetix_cli.bench.env import EnvBenchConfig, bench_env

    config = EnvBenchConfig(
        size=size,
        envs=int_list("--envs", envs),
        observations=name_list(obs),
        steps=steps,
        min_time=min_time,
        seed=seed,
    )
    table = Table("observation", "size", "envs", "compile [s]", "env steps/s")

    def report(r):
        console.print(
            f"{r.observation:16s} size {r.size} envs {r.envs:5d}: compile {r.compile_s:6.1f} s, "
            f"{r.steps_per_s:12,.0f} env steps/s",
            style="dim",
        )
        table.add_row(r.observation, r.size, str(r.envs), f"{r.compile_s:.1f}", f"{r.steps_per_s:,.0f}")

    results = bench_env(config, report)
    console.print(table)
    _write_bench_json(json_path, config, results)


@bench_app.command("gym")
def bench_gym_command(
    levels: str = typer.Option("s", help="Level source: fresh, a suite (s, m, l), a level file or folder."),
    size: str = typer.Option(None, help="Level size: s, m or l (default: what the levels need; m for fresh)."),
    obs: str = typer.Option("symbolic-flat", help="Observation type."),
    envs: str = typer.Option("64,1024", help="Comma-separated batch sizes."),
    steps: int = typer.Option(32, min=1, max=10**5, help="Environment steps per timed scan."),
    min_time: float = typer.Option(3.0, min=0.0, max=3600.0, help="Seconds of timed calls per measurement."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Seed of the resets and actions."),
    json_path: Path = typer.Option(None, "--json", help="Also write the results to this JSON file."),
) -> None:
    """Env steps per second through the gymnax environment and the Gymnasium vector environment, against
    KinetixEnv itself (side by side, one run)."""
    if json_path is not None:
        check_output_file(json_path, "--json")
    from kinetix_cli.bench.gym import GymBenchConfig, bench_gym

    config = GymBenchConfig(
        levels=levels,
        size=size,
        observation=obs,
        envs=int_list("--envs", envs),
        steps=steps,
        min_time=min_time,
        seed=seed,
    )
    table = Table("path", "observation", "envs", "compile [s]", "env steps/s", "vs KinetixEnv")
    direct: dict[int, float] = {}

    def report(r):
        if r.path == "refresh_levels":
            console.print(
                f"refresh_levels   {r.envs:5d} levels: make {r.compile_s:6.1f} s, {r.steps_per_s:12,.0f} levels/s",
                style="dim",
            )
            table.add_row(
                r.path, r.observation, f"{r.envs} levels", f"{r.compile_s:.1f}", f"{r.steps_per_s:,.0f} lv/s", ""
            )
            return
        direct.setdefault(r.envs, r.steps_per_s)
        ratio = f"{r.steps_per_s / direct[r.envs]:.2f}x"
        console.print(
            f"{r.path:16s} envs {r.envs:5d}: compile {r.compile_s:6.1f} s, {r.steps_per_s:12,.0f} env steps/s {ratio}",
            style="dim",
        )
        table.add_row(r.path, r.observation, str(r.envs), f"{r.compile_s:.1f}", f"{r.steps_per_s:,.0f}", ratio)

    results = bench_gym(config, report)
    console.print(table)
    _write_bench_json(json_path, config, results)


@bench_app.command("train")
def bench_train_command(
    size: str = typer.Option("s", help="Level size: s, m or l."),
    models: str = typer.Option("flat-mlp,pi-mlp,transformer", help="Comma-separated models to measure."),
    envs: str = typer.Option("64", help="Comma-separated numbers of parallel environments."),
    steps: int = typer.Option(32, min=1, max=10**5, help="Rollout steps per environment per update."),
    epochs: int = typer.Option(4, min=1, max=4096, help="PPO epochs per update."),
    minibatches: int = typer.Option(4, min=1, max=4096, help="Minibatches per epoch."),
    width: int = typer.Option(128, min=1, max=4096, help="Hidden width of the models."),
    layers: int = typer.Option(5, min=1, max=64, help="Actor and critic hidden layers."),
    compute: str = typer.Option(
        "float32", help="Comma-separated number types the networks compute in: float32, bfloat16 (mixed precision)."
    ),
    min_time: float = typer.Option(5.0, min=0.0, max=3600.0, help="Seconds of timed updates per measurement."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Seed of the levels, parameters and actions."),
    devices: str = typer.Option(
        None, help="Comma-separated local device counts to measure on (default: all; 1 with --breakdown)."
    ),
    breakdown: bool = typer.Option(
        False, "--breakdown", help="Also time each phase alone, the env alone, FLOPs and the matmul limit (1 device)."
    ),
    trace: Path = typer.Option(None, "--trace", help="Write a JAX profiler trace of a few updates per model here."),
    score_levels: int = typer.Option(
        SCORING["score_levels"],
        min=0,
        max=2**24,
        help="With --breakdown, SFL's scoring timed beside the update: levels per refresh (0: none).",
    ),
    score_attempts: int = typer.Option(SCORING["score_attempts"], min=1, max=1024, help="Copies of each scored level."),
    score_steps: int = typer.Option(SCORING["score_steps"], min=1, max=10**5, help="Steps each copy plays."),
    refresh_every: int = typer.Option(SCORING["refresh_every"], min=1, max=INT32_MAX, help="Updates per refresh."),
    json_path: Path = typer.Option(None, "--json", help="Also write the results to this JSON file."),
) -> None:
    """PPO training env steps per second and compile time per model (whole jitted updates), on all local
    devices or per device count (--devices 1,2); with --breakdown, where an update's time goes, and what SFL's
    scoring adds (by default as the general recipe scores: 384 levels x 2 copies x 256 steps every 64 updates)."""
    if json_path is not None:
        check_output_file(json_path, "--json")
    from kinetix_cli.bench.train import TrainBenchConfig, bench_train

    config = TrainBenchConfig(
        size=size,
        models=name_list(models),
        envs=int_list("--envs", envs),
        num_steps=steps,
        epochs=epochs,
        minibatches=minibatches,
        width=width,
        layers=layers,
        computes=name_list(compute),
        min_time=min_time,
        seed=seed,
        devices=None if devices is None else int_list("--devices", devices),
        breakdown=breakdown,
        trace=None if trace is None else str(trace),
        score_levels=score_levels,
        score_attempts=score_attempts,
        score_steps=score_steps,
        refresh_every=refresh_every,
    )
    columns = ("model", "observation", "size", "envs", "compute", "devices", "parameters", "compile [s]", "env steps/s")
    table = Table(*columns)

    def report(r):
        console.print(
            f"{r.model:12s} size {r.size} envs {r.envs:5d} {r.compute} devices {r.devices}: "
            f"compile {r.compile_s:6.1f} s, {r.steps_per_s:10,.0f} env steps/s",
            style="dim",
        )
        row = (r.model, r.observation, r.size, str(r.envs), r.compute, str(r.devices), f"{r.parameters:,}")
        table.add_row(*row, f"{r.compile_s:.1f}", f"{r.steps_per_s:,.0f}")

    results = bench_train(config, report)
    console.print(table)
    for r in results:
        if r.breakdown is not None:
            console.print(_breakdown_table(r))
        if r.trace is not None:
            console.print(f"trace of {r.model}: {r.trace}")
    _write_bench_json(json_path, config, results)


def _breakdown_table(r) -> Table:
    """One measurement's breakdown (`bench.breakdown.Breakdown`): the whole update, the environment alone, each
    phase, and the matmul limit, with time, share, env steps/s, FLOPs and the share of the float32 matmul limit."""
    b = r.breakdown
    title = f"{r.model}, size {r.size}, {r.envs} envs ({r.observation}): one update"
    table = Table("ms", "share", "env steps/s", "GFLOP", "GFLOP/s", "f32 limit", title=title)
    table.columns.insert(0, Column("part", no_wrap=True))
    limit = lambda rate: f"{rate / b.f32_limit_gflop_per_s:.1%}"  # noqa: E731
    whole = (f"{b.update_ms:.1f}", "100%", f"{r.steps_per_s:,.0f}", f"{b.update_gflop:.3g}")
    table.add_row("update", *whole, f"{b.update_gflop_per_s:.3g}", limit(b.update_gflop_per_s))
    table.add_row("env alone", f"{b.env_only_ms:.1f}", "", f"{b.env_only_steps_per_s:,.0f}", "", "", "")
    for p in b.phases:
        rate = p.gflop / (p.ms / 1e3)
        flops = (f"{p.gflop:.3g}", f"{rate:.3g}", limit(rate)) if p.gflop else ("", "", "")
        table.add_row(p.name, f"{p.ms:.1f}", f"{p.share:.0%}", "", *flops)
    table.add_row("phases summed", f"{b.phase_sum_ms:.1f}", f"{b.phase_sum_ms / b.update_ms:.0%}", "", "", "", "")
    s = b.scoring
    if s is not None:
        table.add_row("SFL refresh", f"{s.refresh_ms:.1f}", "", f"{s.steps_per_s:,.0f}", "", "", "")
        table.add_row(f"SFL per update (/{s.refresh_every})", f"{s.per_update_ms:.1f}", f"{s.share:.0%}", *[""] * 4)
    for m in b.matmuls:
        name = f"{'f32' if m.dtype == 'float32' else 'bf16'} {'x'.join(str(n) for n in m.shape)}"
        table.add_row(name, "", "", "", "", f"{m.gflop_per_s:.3g}", limit(m.gflop_per_s))
    counted = "times their trip counts" if b.loops_counted else "counted once"
    table.caption = (
        f"Phases compiled alone; XLA fuses them in the update, so they need not sum to it. Rollout forward: "
        f"a pass per step, and one on the truncated episodes' final observations ({b.final_value_rows} rows; all when "
        f"more were truncated). Matmul rows: the f32 and bf16 limit at the "
        f"update's shapes (rows x inner x cols); best {b.best_limit_gflop_per_s:.3g} GFLOP/s. XLA's own cost of "
        f"the compiled update: {b.xla_update_gflop:.3g} GFLOP (loop bodies {counted})."
    )
    if s is not None:
        table.caption += (
            f" SFL: one refresh scores {s.levels:,} pool levels x {s.attempts} copies x {s.steps} steps every "
            f"{s.refresh_every} updates; its share is of a run's time, updates and scoring."
        )
    return table


@bench_app.command("generate")
def bench_generate_command(
    size: str = typer.Option("s", help="Level size: s, m or l."),
    chunk: int = typer.Option(1024, min=1, max=2**20, help="Levels sampled per device batch."),
    min_time: float = typer.Option(10.0, min=0.0, max=3600.0, help="Seconds of timed chunks after compilation."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Generation seed."),
    json_path: Path = typer.Option(None, "--json", help="Also write the result to this JSON file."),
) -> None:
    """Kept levels per second with the default filters, and compile times."""
    if json_path is not None:
        check_output_file(json_path, "--json")
    from kinetix_cli.bench.generate import GenerateBenchConfig, bench_generate
    from kinetix_cli.generator.filters import make_config

    make_config(size, chunk)  # checks the flags before anything compiles
    config = GenerateBenchConfig(size=size, chunk=chunk, min_time=min_time, seed=seed)
    r = bench_generate(config)
    table = Table("size", "chunk", "sampler compile [s]", "compile [s]", "sampled/s", "kept/s", "kept")
    table.add_row(
        r.size,
        str(r.chunk),
        f"{r.sampler_compile_s:.1f}",
        f"{r.compile_s:.1f}",
        f"{r.sampled_per_s:,.0f}",
        f"{r.kept_per_s:,.0f}",
        f"{r.kept_fraction:.0%}",
    )
    console.print(table)
    _write_bench_json(json_path, config, [r])


@bench_app.command("studio")
def bench_studio_command(
    sizes: str = typer.Option("s,m,l", help="Comma-separated level sizes."),
    steps: int = typer.Option(300, min=10, max=10**5, help="Play steps timed per size."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Seed of the generated levels and random actions."),
    json_path: Path = typer.Option(None, "--json", help="Also write the results to this JSON file."),
) -> None:
    """The level studio's play loop: one step's HTTP round trip on localhost and the frames per second it allows."""
    if json_path is not None:
        check_output_file(json_path, "--json")
    from kinetix_cli.studio.latency import StudioBenchConfig, bench_studio

    chosen = name_list(sizes)
    if not chosen or not set(chosen) <= {"s", "m", "l"}:
        raise UserError(f"--sizes: expected sizes among s, m, l separated by commas, got {sizes!r}")
    config = StudioBenchConfig(sizes=tuple(chosen), steps=steps, seed=seed)
    table = Table("size", "compile [s]", "round trip median [ms]", "p90 [ms]", "in server [ms]", "frames/s")

    def report(r):
        table.add_row(
            r.size, f"{r.compile_s:.1f}", f"{r.median_ms:.1f}", f"{r.p90_ms:.1f}", f"{r.server_ms:.1f}", f"{r.fps:.0f}"
        )

    results = bench_studio(config, report)
    console.print(table)
    _write_bench_json(json_path, config, results)


def _write_bench_json(json_path: Path | None, config, results) -> None:
    """Write a benchmark's machine, versions, config and results (`kinetix-bench/1`) if a path was given."""
    if json_path is None:
        return
    from kinetix_cli.bench.timing import bench_record
    from kinetix_cli.constants import BENCH_FORMAT
    from kinetix_cli.io import atomic_write_json

    atomic_write_json(json_path, bench_record(config, results), BENCH_FORMAT)
    console.print(f"wrote {json_path}")
