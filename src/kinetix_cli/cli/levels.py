"""Commands on level files and level sets: validate, render, rollout, solve, import, and the `levels` group
(list, info, show, sheet, export)."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from kinetix_cli.cli.console import console, say
from kinetix_cli.constants import INT32_MAX
from kinetix_cli.errors import UserError
from kinetix_cli.io import check_output_dir, check_output_file

commands = typer.Typer()
levels_app = typer.Typer(no_args_is_help=True, help="Level files and generated level sets.")


@commands.command("import")
def import_command(
    paths: list[Path] = typer.Argument(
        ..., help="Reference-format level files (Kinetix, KinetixJS) or folders of them."
    ),
    out: Path = typer.Option(..., "-o", "--out", help="Folder to write the converted levels into."),
    report: Path = typer.Option(None, "--report", help="Also write what was not carried over to this JSON file."),
) -> None:
    """Convert reference Kinetix levels into kinetix-level files, listing what could not be carried over."""
    from kinetix_cli.constants import IMPORT_REPORT_FORMAT
    from kinetix_cli.io import atomic_write_json
    from kinetix_cli.levels.files import import_reference_file, import_targets

    check_output_dir(out, "-o")
    if report is not None:
        check_output_file(report, "--report")
    entries = []
    for source, target in import_targets(paths, out):
        notes = import_reference_file(source, target)
        status = (f"{len(notes)} note(s)", "yellow") if notes else ("ok", "green")
        say(status, f" {source} -> {target}")
        for note in notes:
            console.print(f"    {note}")
        entries.append({"source": str(source), "output": str(target), "notes": [vars(n) for n in notes]})
    noted = sum(bool(e["notes"]) for e in entries)
    console.print(f"imported {len(entries)} level(s) into {out}; {noted} with something not carried over")
    if report is not None:
        atomic_write_json(report, {"levels": entries}, IMPORT_REPORT_FORMAT)
        console.print(f"wrote {report}")


@commands.command()
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
    from kinetix_cli.levels.files import level_paths, load_level
    from kinetix_cli.levels.solution import SOLUTION_SETTINGS, check_level, decode_solution

    files = level_paths(paths)
    problems = 0
    for path in files:
        spec = load_level(path)
        if spec.solution is not None:
            decode_solution(spec.solution, str(path), SOLUTION_SETTINGS.max_steps)
        scene = spec.scene
        say(
            ("ok", "green"),
            f" {path}  size {spec.default_size()}  {len(scene.polygons)} polygons, {len(scene.circles)} circles, "
            f"{len(scene.joints)} joints, {len(scene.thrusters)} thrusters{', solution' if spec.solution else ''}",
        )
        if play:
            outcome = check_level(spec, attempts=20)
            solution = outcome.get("solution")
            if solution is None:
                parts = ["    ", ("no solution", "yellow")]
            elif bool(solution.solved[0]):
                parts = [f"    solution solves in {int(solution.length[0])} steps"]
            else:
                parts = ["    ", ("solution does not solve", "red")]
                problems += 1
            if bool(outcome["noop"].solved[0]):
                parts += ["; ", ("no-op solves", "red")]
                problems += 1
            else:
                parts += ["; no-op does not solve"]
            say(*parts, f"; random solves {int(outcome['random'].solved.sum())}/20")
    console.print(f"{len(files)} level file(s) valid")
    if problems:
        say((f"{problems} problem(s) when playing the levels", "red"))
        raise typer.Exit(1)


@commands.command()
def solve(
    level: Path = typer.Argument(..., help="Level file."),
    write: bool = typer.Option(False, "--write", help="Store the solution in the level file."),
    population: int = typer.Option(256, min=8, max=65536, help="Action sequences per iteration."),
    iterations: int = typer.Option(20, min=1, max=10000, help="Most CEM iterations."),
    segments: int = typer.Option(16, min=1, max=256, help="Pieces of constant action per episode."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Random seed."),
) -> None:
    """Find an action sequence that solves a level (cross-entropy method on the batched environment)."""
    if write:
        check_output_file(level, "--write")
    import json

    from kinetix_cli.io import read_json
    from kinetix_cli.levels.files import load_level, save_level
    from kinetix_cli.tools.solve import SolveConfig
    from kinetix_cli.tools.solve import solve as run_solve

    spec = load_level(level)
    config = SolveConfig(population=population, iterations=iterations, segments=segments, seed=seed)

    def report(iteration: int, best: float, solved: float) -> None:
        console.print(f"iteration {iteration:3d}: best fitness {best:8.2f}, solved {solved:6.1%} of the population")

    result = run_solve(spec, config, report)
    if result.solution is None:
        say(("no robust solution", "red"), f" after {result.episodes} episodes ({result.seconds:.0f} s)")
        raise typer.Exit(1)
    say(
        ("solved", "green"),
        f" in {result.length} steps after {result.episodes} episodes ({result.seconds:.0f} s): "
        f"{json.dumps(result.solution)}",
    )
    if write:
        save_level(level, read_json(level) | {"solution": result.solution})
        console.print(f"wrote the solution into {level}")


@commands.command()
def render(
    level: Path = typer.Argument(..., help="Level file."),
    out: Path = typer.Option(..., "-o", "--out", help="PNG file to write."),
    scale: float = typer.Option(120, min=10, max=1000, help="Pixels per metre."),
) -> None:
    """Draw a level as a PNG: roles, joints and motors by binding, thrusters."""
    check_output_file(out, "-o")
    from kinetix_cli.levels.files import load_level
    from kinetix_cli.viz.render import render_level, save_png

    spec = load_level(level)
    save_png(render_level(spec.build(), scale=scale, title=spec.name, caption=spec.description or None), out)
    console.print(f"wrote {out}")


MAX_TILES = 16
"""Most levels `kinetix rollout` draws in one GIF."""


@commands.command()
def rollout(
    levels: list[Path] = typer.Argument(
        ...,
        help="Level files, folders of them or a named suite (s, m, l, validation, test); several play side by side "
        "in one GIF.",
    ),
    policy: str = typer.Option(
        "solution",
        help="noop, random, solution (the level's stored actions), a run or agent folder, or a shipped agent "
        "(kinetix agents).",
    ),
    out: Path = typer.Option(None, "-o", "--out", help="GIF file to write (omit to only print the outcome)."),
    seed: int = typer.Option(
        0, min=0, max=INT32_MAX, help="Seed of the random policy, or of a trained policy's sampled actions."
    ),
    scale: float = typer.Option(80, min=10, max=400, help="Pixels per metre of the GIF (of each tile)."),
    columns: int = typer.Option(
        None,
        min=1,
        max=MAX_TILES,
        help="Tiles per row of a GIF of several levels (default: a square grid, 2 for 4 levels).",
    ),
) -> None:
    """Play one episode of each level and print its return and whether it was solved; optionally as a GIF.

    A trained policy plays in its run's environment (frame skip, episode cap, shaping, observation, action).
    Every level is played on its own with the same policy and seed, as if it were the only one: several levels
    make one GIF of their episodes in a grid (--columns), each tile captioned with its size and how it ended, an
    episode that ends early holding its last frame. Example: the shipped default agent on four of the paper's
    levels (after `make reference-levels`):

        kinetix rollout .cache/reference-levels/s/h7_unicycle_left.json .cache/reference-levels/m/h2_car_right.json
        --policy general --seed 0 -o agent.gif"""
    if out is not None:
        check_output_file(out, "-o")
    import jax

    from kinetix_cli.env.episode import open_loop
    from kinetix_cli.env.factory import make_env
    from kinetix_cli.levels.files import level_paths, load_level
    from kinetix_cli.levels.solution import OPEN_LOOP_POLICIES, SOLUTION_SETTINGS, open_loop_actions
    from kinetix_cli.rl.agents import load_policy, shipped_names
    from kinetix_cli.viz.render import save_gif
    from kinetix_cli.viz.rollout import record_episode, rollout_frames

    paths = level_paths(levels)
    if out is not None and len(paths) > MAX_TILES:
        raise UserError(f"rollout: {len(paths)} levels, but one GIF shows at most {MAX_TILES}")
    if policy in OPEN_LOOP_POLICIES:
        loaded = None
    elif Path(policy).is_dir() or policy in shipped_names():
        loaded = load_policy(policy)
    else:
        choices = ", ".join([*OPEN_LOOP_POLICIES, *shipped_names()])
        raise UserError(f"--policy: {policy!r} is not one of {choices} nor a run or agent folder")
    games = []  # every level's environment and policy first, so a bad level stops the command before any play
    for path in paths:
        spec = load_level(path)
        if loaded is None:
            env, params = make_env(SOLUTION_SETTINGS, spec.default_static())
            horizon = SOLUTION_SETTINGS.max_steps
            act = open_loop(jax.numpy.asarray(open_loop_actions(spec, policy, horizon, seed)))
        else:
            env, params = loaded.env_for(spec.default_size(), str(path))
            horizon, act = loaded.config.env.max_steps, loaded.act
        games.append((spec, env, params, spec.build(env.static), horizon, act))
    played = []
    for spec, env, params, level, horizon, act in games:
        episode = record_episode(env, params, level, act, jax.random.key(seed), horizon)
        ending = (episode.ending, {"solved": "green", "failed": "red"}.get(episode.ending, ""))
        say(
            f"{spec.name}: policy {policy}: ",
            ending,
            f" after {episode.length} steps ({episode.length * episode.step_seconds:.2f} s), "
            f"return {episode.total_return:+.3f}",
        )
        played.append((spec, episode))
    if len(played) > 1:
        console.print(f"solved {sum(e.solved for _, e in played)} of {len(played)} levels")
    if out is None:
        return
    tiles = [(spec.name, spec.default_size(), episode) for spec, episode in played]
    frames, fps = rollout_frames(tiles, scale=scale, columns=columns)
    save_gif(frames, out, fps=fps)
    console.print(f"wrote {out} ({len(frames)} frames)")


@levels_app.command("list")
def levels_list(
    paths: list[Path] = typer.Argument(..., help="Level files or folders of them."),
    markdown: bool = typer.Option(False, "--markdown", help="Print a Markdown table (for levels/README.md)."),
    play: int = typer.Option(
        0, "--play", min=0, help="Also play a no-op and this many random episodes per level (adds two columns)."
    ),
) -> None:
    """One row per level: file, size, entities, solution length and goal (and with --play: no-op, random)."""
    from kinetix_cli.levels.files import level_paths, load_level
    from kinetix_cli.levels.solution import check_level

    rows = []
    for path in level_paths(paths):
        spec = load_level(path)
        scene = spec.scene
        entities = f"{len(scene.polygons)}/{len(scene.circles)}/{len(scene.joints)}/{len(scene.thrusters)}"
        steps = "-"
        if spec.solution is not None:
            steps = str(sum(entry[1] for entry in spec.solution.get("actions", [])))
        row = (str(path), spec.default_size(), entities, steps)
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


@levels_app.command("info")
def levels_info(
    path: Path = typer.Argument(..., help="Level-set folder."),
    json_out: bool = typer.Option(False, "--json", help="Print JSON instead of tables."),
) -> None:
    """A level set's settings, filter statistics and entity counts (and a solved set's solution counts)."""
    import json

    from kinetix_cli.levels.levelset import load_levelset
    from kinetix_cli.levels.stats import level_statistics

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
    if levelset.solutions is not None:
        found = levelset.solutions
        solved = int(found.solved.sum())
        info["solutions"] = {
            "solved": solved,
            "unsolved": len(found.solved) - solved,
            "mean length": float(found.length[found.solved].mean()) if solved else None,
        }
    if json_out:
        print(json.dumps(info, indent=2))
        return
    say((str(path), "bold"), f": {info['count']:,} size-{info['size']} levels, seed {info['seed']}")
    if "solutions" in info:
        row = info["solutions"]
        length = "" if row["mean length"] is None else f" (in {row['mean length']:.0f} steps on average)"
        console.print(f"solutions: {row['solved']:,} solved{length}, {row['unsolved']:,} not solved by the search")
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
    path: Path = typer.Argument(..., help="Level-set folder, or a run directory with --buffer."),
    index: int = typer.Option(0, min=0, help="The level to draw (with --grid: the first one)."),
    grid: int = typer.Option(0, min=0, max=1024, help="Draw this many levels from --index on as a contact sheet."),
    buffer: bool = typer.Option(False, "--buffer", help="Draw a training run's curriculum buffer, best first."),
    out: Path = typer.Option(..., "-o", "--out", help="PNG file to write."),
) -> None:
    """Render one level of a set, or a contact sheet of several; with --buffer, the levels of a run's curriculum
    buffer (latest checkpoint), highest score first (SFL: learnability), each with its solve rate and score when it
    was last played."""
    check_output_file(out, "-o")
    import math

    from kinetix_cli.levels.levelset import level_at, load_levelset
    from kinetix_cli.viz.buffer import buffer_levels
    from kinetix_cli.viz.contact_sheet import contact_sheet
    from kinetix_cli.viz.render import render_level, save_png

    if buffer:
        levels = buffer_levels(path, index, max(grid, 1))
        if not levels:
            raise UserError(f"{path}: the curriculum buffer is empty at the latest checkpoint")
        image = contact_sheet(levels, columns=math.ceil(math.sqrt(len(levels))))
        save_png(image, out)
        say(f"wrote {out} ({len(levels)} buffer levels)")
        return
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
    check_output_file(out, "-o")
    import math

    from kinetix_cli.levels.files import level_paths, load_level
    from kinetix_cli.viz.contact_sheet import contact_sheet
    from kinetix_cli.viz.render import save_png

    levels = [(load_level(path).build(), path.stem) for path in level_paths(paths)]
    save_png(contact_sheet(levels, columns=columns or math.ceil(math.sqrt(len(levels))), scale=scale), out)
    console.print(f"wrote {out} ({len(levels)} levels)")


@levels_app.command("export")
def levels_export(
    path: Path = typer.Argument(..., help="Level-set folder."),
    index: int | None = typer.Option(None, help="The level to export, to the file -o."),
    first: int | None = typer.Option(
        None,
        min=1,
        help="Export levels 0 .. FIRST-1 into the folder -o, as <set>-00000.json, ... (e.g. a held-out suite).",
    ),
    out: Path = typer.Option(..., "-o", "--out", help="Level file (JSON) to write (--index) or folder (--first)."),
) -> None:
    """Write one level of a set (--index) or its first levels (--first) as level files (kinetix-level/1) that
    validate, render, rollout and eval read."""
    if (index is None) == (first is None):
        raise UserError(
            "levels export: give exactly one of --index N (one level, -o a file) and --first N (-o a folder)"
        )
    if first is None:
        check_output_file(out, "-o")
    else:
        check_output_dir(out, "-o")
    from kinetix_cli.levels.export import export_set_level
    from kinetix_cli.levels.files import save_level
    from kinetix_cli.levels.levelset import load_levelset

    levelset = load_levelset(path)
    if first is None:
        save_level(out, export_set_level(levelset, path, index))
        console.print(f"wrote {out}")
        return
    count = levelset.manifest["count"]
    if first > count:
        raise UserError(f"--first: {first} levels asked for; {path} has {count}")
    exported = [export_set_level(levelset, path, i) for i in range(first)]  # a level it cannot hold: no file written
    out.mkdir(parents=True, exist_ok=True)
    for i, data in enumerate(exported):
        save_level(out / f"{path.name}-{i:05d}.json", data)
    console.print(f"wrote {first} level files to {out}")


@levels_app.command("mirror")
def levels_mirror(
    paths: list[Path] = typer.Argument(
        ..., help="A level-set folder, or level files, folders of them and suite names (s, m, l, validation, test)."
    ),
    out: Path = typer.Option(
        ...,
        "-o",
        "--out",
        help="The mirrored set's folder; for level files a folder (files keep their names, under the name of the "
        "folder they came from), or a .json file for one level.",
    ),
) -> None:
    """Write the left-right mirror images (x -> 5 - x) of levels: every body, joint, thruster and the gravity
    reflected, a level file's solution mirrored with it (motors' forward and backward swap), so `kinetix validate`
    replays it. The mirror images of the paper's levels are test levels too."""
    from kinetix_cli.levels.levelset import MANIFEST_FILE

    if len(paths) == 1 and (paths[0] / MANIFEST_FILE).is_file():
        _mirror_set(paths[0], out)
        return
    from kinetix_cli.levels.files import level_paths, load_level, save_level
    from kinetix_cli.levels.mirror import mirrored_level_data
    from kinetix_cli.levels.suites import resolve_suite

    sources = [
        (file, _mirrored_name(file, root))
        for named in paths
        for root in resolve_suite(named)
        for file in level_paths([root])
    ]
    if len(sources) == 1 and out.suffix == ".json":
        check_output_file(out, "-o")
        targets = [(sources[0][0], out)]
    else:
        check_output_dir(out, "-o")
        targets = [(file, out / name) for file, name in sources]
        clash = next((t for i, (_, t) in enumerate(targets) if t in {u for _, u in targets[:i]}), None)
        if clash is not None:
            raise UserError(f"-o: two levels would be written to {clash}; mirror them into separate folders")
    written = [(target, mirrored_level_data(load_level(file))) for file, target in targets]  # all checked first
    for target, data in written:
        target.parent.mkdir(parents=True, exist_ok=True)
        save_level(target, data)
    console.print(f"wrote {len(written)} mirrored level file{'s' if len(written) != 1 else ''} to {out}")


def _mirrored_name(file: Path, root: Path) -> Path:
    """Where a mirrored level goes under -o: a file named on its own by its name, a file of a folder by its path
    under the folder's name (`levels/validation/s/x.json` from `validation` -> `s/x.json`)."""
    return Path(file.name) if root == file else Path(root.name) / file.relative_to(root)


def _mirror_set(source: Path, out: Path) -> None:
    from kinetix_cli.levels.mirror import mirror_levelset

    check_output_dir(out, "-o")
    manifest = mirror_levelset(source, out, progress=lambda kept, stats: say(f"  {kept:,} levels mirrored"))
    console.print(f"wrote {out}: {manifest['count']:,} mirrored levels of {source} (size {manifest['size']})")


@levels_app.command("solve")
def levels_solve(
    path: Path = typer.Argument(..., help="Level-set folder (kinetix generate)."),
    out: Path = typer.Option(
        ..., "-o", "--out", help="Folder of the solved set to write (a killed solve resumes at its last written shard)."
    ),
    population: int = typer.Option(64, min=8, max=65536, help="Action sequences per level and iteration."),
    iterations: int = typer.Option(10, min=1, max=10000, help="Most CEM iterations per level."),
    segments: int = typer.Option(16, min=1, max=256, help="Pieces of constant action per episode."),
    batch: int = typer.Option(64, min=1, max=65536, help="Levels searched at once."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Random seed of the search."),
    shard_size: int | None = typer.Option(
        None, min=1, max=2**20, help="Levels per shard file, so how much a killed solve keeps [default: the set's]."
    ),
) -> None:
    """Search a solution for every level of a set (the cross-entropy method of `kinetix solve`, many levels at once)
    and write the solved set: the levels with their solutions, the unsolved marked (`kinetix levels info` counts
    them). Observations are not stored: replaying a solution gives them."""
    check_output_dir(out, "-o")
    from kinetix_cli.tools.solve import SolveConfig, solve_levelset

    config = SolveConfig(population=population, iterations=iterations, segments=segments, seed=seed)
    manifest = solve_levelset(
        path,
        out,
        config,
        batch,
        progress=lambda kept, stats: say(f"  {kept:,} levels searched, {stats['solved']:,} solved"),
        shard_size=shard_size,
    )
    stats = manifest["stats"]
    console.print(f"wrote {out}: {stats['solved']:,} of {manifest['count']:,} levels solved, {stats['unsolved']:,} not")
