"""`kinetix generate`: sample, filter and write a level set."""

from __future__ import annotations

from pathlib import Path

import typer

from kinetix_cli.cli.console import console
from kinetix_cli.cli.processes import COORDINATOR, DEVICES, NUM_PROCESSES, PROCESS_ID, joined
from kinetix_cli.constants import VALIDATION_SEED
from kinetix_cli.io import check_output_dir

commands = typer.Typer()


@commands.command()
def generate(
    size: str = typer.Option("s", help="Level size: s, m or l."),
    count: int = typer.Option(..., min=1, max=10**8, help="Distinct levels to keep."),
    seed: int = typer.Option(
        0,
        min=0,
        max=VALIDATION_SEED - 1,
        help="Seed; the same command gives byte-identical files (the seeds above are the validation suite's).",
    ),
    out: Path = typer.Option(..., "--out", help="Level-set folder (created; an unfinished one is resumed)."),
    filters: str = typer.Option("noop,random", "--filter", help="Drop levels solved by: noop, random, both or none."),
    random_attempts: int = typer.Option(3, min=1, max=100, help="Random-policy episodes per level (random filter)."),
    random_max_rate: float = typer.Option(0.5, help="Drop levels random play solves more often than this."),
    chunk: int = typer.Option(1024, min=1, max=2**20, help="Levels sampled per device batch."),
    shard_size: int = typer.Option(4096, min=1, max=2**20, help="Levels per shard file."),
    devices: int = DEVICES,
    coordinator: str = COORDINATOR,
    num_processes: int = NUM_PROCESSES,
    process_id: int = PROCESS_ID,
) -> None:
    """Sample levels, drop trivial ones, and write a level set (manifest + shards), resumably. Each chunk is
    split over all local devices (or --devices N) of one process or of several (--coordinator, ...); the set is
    the same at any device or process count."""
    check_output_dir(out, "--out")
    with joined(coordinator, num_processes, process_id):
        _generate(size, count, seed, out, filters, random_attempts, random_max_rate, chunk, shard_size, devices)


def _generate(size, count, seed, out, filters, random_attempts, random_max_rate, chunk, shard_size, devices) -> None:
    import contextlib

    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from kinetix_cli.generator.filters import FilterConfig, chunk_source, make_config, parse_filters
    from kinetix_cli.levels.levelset import generate_levelset
    from kinetix_cli.parallel import is_primary, make_mesh

    noop, random = parse_filters(filters)
    filter_config = FilterConfig(noop, random_attempts if random else 0, random_max_rate)
    config = make_config(size, chunk, filter_config)
    mesh = make_mesh(devices)  # one chunk per device at a time
    columns = (TextColumn("generating"), BarColumn(), MofNCompleteColumn(), TextColumn("{task.fields[info]}"))
    shown = Progress(*columns, TimeElapsedColumn(), console=console) if is_primary() else contextlib.nullcontext()
    with shown as bar:
        info = "compiling the sampler and filters..."
        task = bar.add_task("generate", total=count, info=info) if bar is not None else None
        start: list[float] = []  # time and kept count after the first chunk (which includes compilation)

        def report(kept: int, stats: dict) -> None:
            import time

            start.extend([] if start else [time.perf_counter(), kept])
            rate = (kept - start[1]) / max(time.perf_counter() - start[0], 1e-9)
            sampled = max(stats.get("sampled", 0), 1)
            info = f"{rate:,.0f} kept levels/s, kept {kept / sampled:.0%} of {sampled:,} sampled"
            if bar is not None:
                bar.update(task, completed=kept, info=info if rate else "first chunk done")

        manifest = generate_levelset(
            out,
            size=size,
            count=count,
            seed=seed,
            settings=config.settings(),
            chunk_fn=chunk_source(config, seed, mesh),
            shard_size=shard_size,
            progress=report,
        )
    stats = ", ".join(f"{k} {v:,}" for k, v in manifest["stats"].items())
    if is_primary():
        console.print(
            f"wrote {out}: {manifest['count']:,} {size} levels in {len(manifest['shards'])} shard(s); {stats}"
        )
