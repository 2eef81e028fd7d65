"""The `kinetix` command line. Each command builds a config and calls one library function."""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

import typer
from rich.console import Console
from rich.table import Table

from kinetix_cli.cli_bench import bench_app
from kinetix_cli.errors import UserError

app = typer.Typer(no_args_is_help=True, add_completion=False, help="kinetix: open-ended 2D physics RL in JAX.")
app.add_typer(bench_app, name="bench")
levels_app = typer.Typer(no_args_is_help=True, help="Level files and generated level sets.")
app.add_typer(levels_app, name="levels")
console = Console(soft_wrap=True)  # text lines stay whole when piped; tables still fit the width


def _level_paths(paths: list[Path]) -> list[Path]:
    from kinetix_cli.level_file import level_paths

    return level_paths(paths)


@app.command("import")
def import_command(
    paths: list[Path] = typer.Argument(
        ..., help="Reference-format level files (Kinetix, KinetixJS) or folders of them."
    ),
    out: Path = typer.Option(..., "-o", "--out", help="Folder to write the converted levels into."),
    report: Path = typer.Option(None, "--report", help="Also write what was not carried over to this JSON file."),
) -> None:
    """Convert reference Kinetix levels into kinetix-level files, listing what could not be carried over."""
    from kinetix_cli.io import atomic_write_json
    from kinetix_cli.reference_level import IMPORT_REPORT_FORMAT, import_reference_file

    entries = []
    for path in paths:
        files = _level_paths([path])
        for source in files:
            target = out / (source.relative_to(path) if path.is_dir() else source.name)
            notes = import_reference_file(source, target)
            status = f"[yellow]{len(notes)} note(s)[/yellow]" if notes else "[green]ok[/green]"
            console.print(f"{status} {source} -> {target}", highlight=False)
            for note in notes:
                console.print(f"    {note}", highlight=False)
            entries.append({"source": str(source), "output": str(target), "notes": [vars(n) for n in notes]})
    noted = sum(bool(e["notes"]) for e in entries)
    console.print(f"imported {len(entries)} level(s) into {out}; {noted} with something not carried over")
    if report is not None:
        atomic_write_json(report, {"levels": entries}, IMPORT_REPORT_FORMAT)
        console.print(f"wrote {report}")


@app.command()
def validate(
    paths: list[Path] = typer.Argument(..., help="Level files or folders of them."),
    play: bool = typer.Option(
        False,
        "--play",
        help="Also replay each solution, a no-op policy and 20 random policies (exit 1 if a "
        "solution fails or the no-op solves).",
    ),
) -> None:
    """Check level files; stop with exit code 2 at the first bad one."""
    from kinetix_cli.level_file import load_level
    from kinetix_cli.solve import check_level, decode_solution

    files = _level_paths(paths)
    problems = 0
    for path in files:
        spec = load_level(path)
        if spec.solution is not None:
            decode_solution(spec.solution, str(path), 256)
        static = spec.default_static()
        console.print(
            f"[green]ok[/green] {path}  size {_size_name(static)}  {len(spec.scene.polygons)} polygons, "
            f"{len(spec.scene.circles)} circles, {len(spec.scene.joints)} joints, "
            f"{len(spec.scene.thrusters)} thrusters{', solution' if spec.solution else ''}",
            highlight=False,
        )
        if play:
            outcome = check_level(spec, attempts=20)
            solution = outcome.get("solution")
            lines = []
            if solution is None:
                lines.append("[yellow]no solution[/yellow]")
            elif bool(solution.solved[0]):
                lines.append(f"solution solves in {int(solution.length[0])} steps")
            else:
                lines.append("[red]solution does not solve[/red]")
                problems += 1
            if bool(outcome["noop"].solved[0]):
                lines.append("[red]no-op solves[/red]")
                problems += 1
            else:
                lines.append("no-op does not solve")
            lines.append(f"random solves {int(outcome['random'].solved.sum())}/20")
            console.print("    " + "; ".join(lines))
    console.print(f"{len(files)} level file(s) valid")
    if problems:
        console.print(f"[red]{problems} problem(s) when playing the levels[/red]")
        raise typer.Exit(1)


@levels_app.command("list")
def levels_list(
    paths: list[Path] = typer.Argument(..., help="Level files or folders of them."),
    markdown: bool = typer.Option(False, "--markdown", help="Print a Markdown table (for levels/README.md)."),
    play: int = typer.Option(
        0, "--play", min=0, help="Also play a no-op and this many random episodes per level (adds two columns)."
    ),
) -> None:
    """One row per level: file, size, entities, solution length and goal (and with --play: no-op, random)."""
    from kinetix_cli.level_file import load_level
    from kinetix_cli.solve import check_level

    rows = []
    for path in _level_paths(paths):
        spec = load_level(path)
        scene = spec.scene
        entities = f"{len(scene.polygons)}/{len(scene.circles)}/{len(scene.joints)}/{len(scene.thrusters)}"
        steps = "-"
        if spec.solution is not None:
            steps = str(sum(entry[1] for entry in spec.solution.get("actions", [])))
        row = (str(path), _size_name(spec.default_static()), entities, steps)
        if play:
            outcome = check_level(spec, attempts=play)
            noop = "yes" if bool(outcome["noop"].solved[0]) else "no"
            row += (noop, f"{int(outcome['random'].solved.sum())}/{play}")
        rows.append((*row, spec.description))
    header = ("level", "size", "polygons/circles/joints/thrusters", "solution actions")
    header += ("no-op solves", "random solves") if play else ()
    header += ("goal",)
    if markdown:
        print("| " + " | ".join(header) + " |")
        print("|" + "---|" * len(header))
        for row in rows:
            print("| " + " | ".join(row) + " |")
        return
    table = Table(*header)
    for row in rows:
        table.add_row(*row)
    console.print(table)


@app.command()
def generate(
    size: str = typer.Option("s", help="Level size: s, m or l."),
    count: int = typer.Option(..., min=1, help="Distinct levels to keep."),
    seed: int = typer.Option(0, help="Seed; the same command gives byte-identical files."),
    out: Path = typer.Option(..., "--out", help="Level-set folder (created; an unfinished one is resumed)."),
    filters: str = typer.Option("noop,random", "--filter", help="Drop levels solved by: noop, random, both or none."),
    random_attempts: int = typer.Option(3, min=1, help="Random-policy episodes per level (random filter)."),
    random_max_rate: float = typer.Option(0.5, help="Drop levels random play solves more often than this."),
    chunk: int = typer.Option(1024, min=1, help="Levels sampled per device batch."),
    shard_size: int = typer.Option(4096, min=1, help="Levels per shard file."),
) -> None:
    """Sample levels, drop trivial ones, and write a level set (manifest + shards), resumably."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from kinetix_cli.generate import FilterConfig, generate_chunk, make_config, parse_filters
    from kinetix_cli.levelset import generate_levelset

    noop, random = parse_filters(filters)
    filter_config = FilterConfig(noop, random_attempts if random else 0, random_max_rate)
    config = make_config(size, chunk, filter_config)
    columns = (TextColumn("generating"), BarColumn(), MofNCompleteColumn(), TextColumn("{task.fields[info]}"))
    with Progress(*columns, TimeElapsedColumn(), console=console) as bar:
        task = bar.add_task("generate", total=count, info="compiling the sampler and filters...")
        start: list[float] = []  # time and kept count after the first chunk (which includes compilation)

        def report(kept: int, stats: dict) -> None:
            import time

            start.extend([] if start else [time.perf_counter(), kept])
            rate = (kept - start[1]) / max(time.perf_counter() - start[0], 1e-9)
            sampled = max(stats.get("sampled", 0), 1)
            info = f"{rate:,.0f} kept levels/s, kept {kept / sampled:.0%} of {sampled:,} sampled"
            bar.update(task, completed=kept, info=info if rate else "first chunk done")

        manifest = generate_levelset(
            out,
            size=size,
            count=count,
            seed=seed,
            settings=config.settings(),
            chunk_fn=lambda i: generate_chunk(config, seed, i),
            shard_size=shard_size,
            progress=report,
        )
    stats = ", ".join(f"{k} {v:,}" for k, v in manifest["stats"].items())
    console.print(f"wrote {out}: {manifest['count']:,} {size} levels in {len(manifest['shards'])} shard(s); {stats}")


@app.command()
def pretrain(
    config: Path = typer.Option(..., "--config", help="Experiment config (YAML), e.g. experiments/cpu-small.yaml."),
    run_dir: Path = typer.Option(..., "--run-dir", help="Folder for config, metrics and checkpoints."),
    levels: Path = typer.Option(None, "--levels", help="Train on this level set instead of generated levels."),
    resume: bool = typer.Option(False, "--resume", help="Continue the run from its latest checkpoint."),
    overrides: list[str] = typer.Option([], "--set", help="Override a config value: --set ppo.lr=3e-4."),
    wandb: str = typer.Option(None, "--wandb", help="Also log to Weights & Biases: offline or online."),
) -> None:
    """Train a PPO agent (PureJaxRL-style, jitted) on generated levels or a level set."""

    from kinetix_cli.config import load_config

    extra = ["levels.source=levelset", f"levels.levelset={levels}"] if levels else []
    extra += [f"run.wandb={wandb}"] if wandb else []
    _train_with_progress(load_config(config, [*extra, *overrides]), run_dir, resume)


def _train_with_progress(experiment, run_dir: Path, resume: bool, init_params=None) -> None:
    """Run `train` under a rich progress bar (steps, SPS, return, solve rate, ETA)."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

    from kinetix_cli.train import train

    p = experiment.ppo
    columns = (TextColumn("training"), BarColumn(), TextColumn("{task.fields[info]}"), TimeElapsedColumn())
    with Progress(*columns, TextColumn("ETA"), TimeRemainingColumn(), console=console) as bar:
        task = bar.add_task("train", total=p.num_updates * p.batch_size, info="levels and compile...")

        last_eval = ""

        def report(r: dict) -> None:
            nonlocal last_eval
            if "eval_solve_rate" in r:
                last_eval = f", eval {r['eval_solve_rate']:.0%}"
            info = f"{r['steps']:,} steps, {r['sps']:,.0f} SPS, return {r['return']:+.2f}"
            info += f", solve rate {r['solve_rate']:.0%}{last_eval}"
            bar.update(task, completed=r["steps"], info=info)

        train(experiment, run_dir, resume=resume, progress=report, init_params=init_params)
    console.print(f"wrote {run_dir}: config.yaml, metrics.jsonl, checkpoints/")


@app.command()
def finetune(
    levels: list[Path] = typer.Argument(..., help="Level files or folders to train on (one size)."),
    source: str = typer.Option(..., "--from", help="Run directory or checkpoint to start from, or 'none' (scratch)."),
    run_dir: Path = typer.Option(..., "--run-dir", help="Folder for config, metrics and checkpoints."),
    config: Path = typer.Option(Path("experiments/finetune.yaml"), "--config", help="Experiment config (YAML)."),
    resume: bool = typer.Option(False, "--resume", help="Continue the run from its latest checkpoint."),
    overrides: list[str] = typer.Option([], "--set", help="Override a config value: --set ppo.lr=3e-4."),
) -> None:
    """Train on hand-made levels, starting from a trained agent (--from RUN) or from scratch (--from none).

    With --from RUN the model and observation settings come from that run, so its parameters fit; --from none
    uses the config's, so pass the same --set values to compare the two at equal settings."""
    import dataclasses

    from kinetix_cli.config import load_config
    from kinetix_cli.evaluate import load_policy
    from kinetix_cli.level_file import load_level

    files = _level_paths(levels)
    sizes = {_size_name(load_level(path).default_static()) for path in files}
    if len(sizes) != 1:
        raise UserError(f"finetune: the levels have sizes {', '.join(sorted(sizes))}; give levels of one size")
    listed = "[" + ", ".join(str(path) for path in files) + "]"
    settings = [f"env.size={sizes.pop()}", "levels.source=files", f"levels.files={listed}"]
    settings += [f"run.eval_levels={listed}"]  # evaluate on the fine-tuning levels, unless --set says otherwise
    experiment = load_config(config, [*settings, *overrides])
    params = None
    if source != "none":
        pretrained, params, _ = load_policy(source)
        env = dataclasses.replace(experiment.env, observation=pretrained.env.observation, action=pretrained.env.action)
        experiment = dataclasses.replace(experiment, env=env, model=pretrained.model)
    _train_with_progress(experiment, run_dir, resume, params)


@app.command("eval")
def eval_command(
    policy: Path = typer.Argument(..., help="Run directory (latest checkpoint) or RUN/checkpoints/<update>."),
    levels: list[Path] = typer.Option([Path("levels/s")], "--levels", help="Level files or folders (repeatable)."),
    attempts: int = typer.Option(20, min=1, help="Stochastic episodes per level."),
    seed: int = typer.Option(0, help="Seed of the sampled actions."),
    json_path: Path = typer.Option(None, "--json", help="Also write the results to this JSON file."),
) -> None:
    """Solve rate, return and episode length of a trained policy per level and per suite."""
    import dataclasses

    from kinetix_cli.evaluate import EVAL_FORMAT, evaluate, load_policy, suite_summary
    from kinetix_cli.io import atomic_write_json

    config, params, update = load_policy(policy)
    results = evaluate(config, params, _level_paths(levels), attempts, seed)
    table = Table("level", "solve rate", "return", "length")
    for r in results:
        table.add_row(r.level, f"{r.solve_rate:.0%}", f"{r.mean_return:+.2f}", f"{r.mean_length:.0f}")
    summary = suite_summary(results)
    for name, row in summary.items():
        table.add_row(f"[bold]{name}[/bold] ({row['levels']} levels)", f"{row['solve_rate']:.0%}", "", "")
    console.print(table)
    if json_path is not None:
        payload = {
            "policy": str(policy),
            "update": update,
            "attempts": attempts,
            "seed": seed,
            "levels": [dataclasses.asdict(r) for r in results],
            "suites": summary,
        }
        atomic_write_json(json_path, payload, EVAL_FORMAT)
        console.print(f"wrote {json_path}")


@levels_app.command("info")
def levels_info(
    path: Path = typer.Argument(..., help="Level-set folder."),
    json_out: bool = typer.Option(False, "--json", help="Print JSON instead of tables."),
) -> None:
    """A level set's settings, filter statistics and entity counts."""
    import json

    from kinetix_cli.levelset import load_levelset
    from kinetix_cli.levelset_stats import level_statistics

    levelset = load_levelset(path)
    manifest = levelset.manifest
    info = {
        "path": str(path),
        "format": manifest.get("format"),
        "size": manifest["size"],
        "count": manifest["count"],
        "seed": manifest["seed"],
        "version": manifest.get("version"),
        "generation": manifest["stats"],
        "settings": manifest["settings"],
        "statistics": level_statistics(manifest["size"], levelset.levels),
    }
    if json_out:
        print(json.dumps(info, indent=2))
        return
    console.print(f"[bold]{path}[/bold]: {info['count']:,} size-{info['size']} levels, seed {info['seed']}")
    console.print("generation: " + ", ".join(f"{k} {v:,}" for k, v in info["generation"].items()))
    stats = info["statistics"]
    table = Table("per level", "mean", "min", "max")
    for name, row in stats["per level"].items():
        table.add_row(name, f"{row['mean']:.2f}", str(row["min"]), str(row["max"]))
    console.print(table)
    floor = ", ".join(f"{k} {v:,}" for k, v in stats["floor role"].items())
    console.print(
        f"levels with a motor {stats['levels with a motor']:,}, with a thruster {stats['levels with a thruster']:,}, "
        f"with red {stats['levels with red']:,}; floor role: {floor}"
    )


@levels_app.command("show")
def levels_show(
    path: Path = typer.Argument(..., help="Level-set folder."),
    index: int = typer.Option(0, help="The level to draw (with --grid: the first one)."),
    grid: int = typer.Option(0, min=0, help="Draw this many levels from --index on as a contact sheet."),
    out: Path = typer.Option(..., "-o", "--out", help="PNG file to write."),
) -> None:
    """Render one level of a set, or a contact sheet of several."""
    import math

    from kinetix_cli.contact_sheet import contact_sheet
    from kinetix_cli.levelset import level_at, load_levelset
    from kinetix_cli.render import render_level, save_png

    levelset = load_levelset(path)
    if grid:
        last = min(index + grid, levelset.manifest["count"])
        levels = [(level_at(levelset, i), f"level {i}") for i in range(index, max(last, index + 1))]
        image = contact_sheet(levels, columns=math.ceil(math.sqrt(len(levels))))
    else:
        image = render_level(level_at(levelset, index), title=f"{path.name} level {index}")
    save_png(image, out)
    console.print(f"wrote {out}")


@levels_app.command("sheet")
def levels_sheet(
    paths: list[Path] = typer.Argument(..., help="Level files or folders of them."),
    out: Path = typer.Option(..., "-o", "--out", help="PNG file to write."),
    columns: int = typer.Option(0, min=0, help="Tiles per row (default: about square)."),
    scale: float = typer.Option(40, min=5, max=500, help="Pixels per metre of each tile."),
) -> None:
    """Draw level files side by side in one PNG, each under its file name."""
    import math

    from kinetix_cli.contact_sheet import contact_sheet
    from kinetix_cli.level_file import load_level
    from kinetix_cli.render import save_png

    levels = [(load_level(path).build(), path.stem) for path in _level_paths(paths)]
    save_png(contact_sheet(levels, columns=columns or math.ceil(math.sqrt(len(levels))), scale=scale), out)
    console.print(f"wrote {out} ({len(levels)} levels)")


@levels_app.command("export")
def levels_export(
    path: Path = typer.Argument(..., help="Level-set folder."),
    index: int = typer.Option(..., help="The level to export."),
    out: Path = typer.Option(..., "-o", "--out", help="Level file (JSON) to write."),
) -> None:
    """Write one level of a set as a level file (kinetix-level/1) that validate, render and rollout read."""
    from engine import SIZES
    from kinetix_cli.io import atomic_write_text
    from kinetix_cli.level_export import export_level
    from kinetix_cli.level_file import format_level_json
    from kinetix_cli.levelset import level_at, load_levelset

    levelset = load_levelset(path)
    size = levelset.manifest["size"]
    try:
        data = export_level(
            level_at(levelset, index),
            SIZES[size],
            name=f"{path.name} {index}",
            description=f"Generated level {index} of {path} (seed {levelset.manifest['seed']}): make green touch blue",
        )
    except ValueError as exc:
        raise UserError(f"{path}: level {index} cannot be written as a level file: {exc}") from None
    atomic_write_text(out, format_level_json(data))
    console.print(f"wrote {out}")


def _size_name(static) -> str:
    from engine import SIZES

    return next((name for name, s in SIZES.items() if s == static), "custom")


@app.command()
def solve(
    level: Path = typer.Argument(..., help="Level file."),
    write: bool = typer.Option(False, "--write", help="Store the solution in the level file."),
    population: int = typer.Option(256, min=8, help="Action sequences per iteration."),
    iterations: int = typer.Option(20, min=1, help="Most CEM iterations."),
    segments: int = typer.Option(16, min=1, max=256, help="Pieces of constant action per episode."),
    seed: int = typer.Option(0, help="Random seed."),
) -> None:
    """Find an action sequence that solves a level (cross-entropy method on the batched environment)."""
    import json

    from kinetix_cli.io import atomic_write_text
    from kinetix_cli.level_file import format_level_json, load_level
    from kinetix_cli.solve import SolveConfig
    from kinetix_cli.solve import solve as run_solve

    spec = load_level(level)
    config = SolveConfig(population=population, iterations=iterations, segments=segments, seed=seed)

    def report(iteration: int, best: float, solved: float) -> None:
        console.print(f"iteration {iteration:3d}: best fitness {best:8.2f}, solved {solved:6.1%} of the population")

    result = run_solve(spec, config, report)
    if result.solution is None:
        console.print(f"[red]no robust solution[/red] after {result.episodes} episodes ({result.seconds:.0f} s)")
        raise typer.Exit(1)
    console.print(
        f"[green]solved[/green] in {result.length} steps after {result.episodes} episodes ({result.seconds:.0f} s): "
        f"{json.dumps(result.solution)}",
        highlight=False,
    )
    if write:
        data = json.loads(level.read_text())
        data["solution"] = result.solution
        atomic_write_text(level, format_level_json(data))
        console.print(f"wrote the solution into {level}")


@app.command()
def render(
    level: Path = typer.Argument(..., help="Level file."),
    out: Path = typer.Option(..., "-o", "--out", help="PNG file to write."),
    scale: float = typer.Option(120, min=10, max=1000, help="Pixels per metre."),
) -> None:
    """Draw a level as a PNG: roles, joints and motors by binding, thrusters."""
    from kinetix_cli.level_file import load_level
    from kinetix_cli.render import render_level, save_png

    spec = load_level(level)
    caption = spec.description or None
    save_png(render_level(spec.build(), scale=scale, title=spec.name, caption=caption), out)
    console.print(f"wrote {out}")


@app.command()
def rollout(
    level: Path = typer.Argument(..., help="Level file."),
    policy: str = typer.Option(
        "solution", help="noop, random, solution (the level's stored actions) or a training run directory."
    ),
    out: Path = typer.Option(None, "-o", "--out", help="GIF file to write (omit to only print the outcome)."),
    seed: int = typer.Option(0, help="Seed of the random policy."),
    scale: float = typer.Option(80, min=10, max=400, help="Pixels per metre of the GIF."),
) -> None:
    """Play one episode of a level and print its return and whether it was solved; optionally as a GIF."""
    from kinetix_cli.level_file import load_level
    from kinetix_cli.rollout import POLICIES, episode_frames, record_episode

    spec = load_level(level)
    actions = None
    if policy not in POLICIES:
        if not Path(policy).is_dir():
            raise UserError(f"--policy: {policy!r} is not one of {', '.join(POLICIES)} nor a run directory")
        from kinetix_cli.evaluate import load_policy, policy_actions

        config, params, _ = load_policy(policy)
        actions = policy_actions(config, params, spec, seed)
    episode = record_episode(spec, policy, seed, actions=actions)
    ending = "[green]solved[/green]" if episode.solved else "[red]failed[/red]" if episode.failed else "timed out"
    console.print(
        f"{spec.name}: policy {policy}: {ending} after {episode.length} steps "
        f"({episode.length * episode.step_seconds:.2f} s), return {episode.total_return:+.3f}"
    )
    if out is not None:
        from kinetix_cli.render import save_gif

        save_gif(episode_frames(spec, episode, scale=scale), out, fps=1.0 / episode.step_seconds)
        console.print(f"wrote {out} ({episode.length + 1} frames)")


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


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings print as one line on stderr (a converted level's notes, for example), without a source line."""
    Console(stderr=True, soft_wrap=True).print(f"[yellow]warning:[/yellow] {message}", highlight=False)


def main() -> None:
    """Entry point: run the app; user errors print one line and exit with code 2.

    Compiled functions are cached on disk (`~/.cache/kinetix/jax`, or $JAX_COMPILATION_CACHE_DIR; set it
    to an empty string to turn the cache off), so a second run of a command skips most of its compile time.
    """
    os.environ.setdefault("JAX_COMPILATION_CACHE_DIR", str(Path.home() / ".cache" / "kinetix" / "jax"))
    warnings.showwarning = _show_warning
    try:
        app()
    except UserError as exc:
        Console(stderr=True, soft_wrap=True).print(f"[red]error:[/red] {exc}", highlight=False)
        sys.exit(exc.exit_code)
