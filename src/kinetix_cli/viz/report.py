"""A static report of training runs (`kinetix report`): one page a person opens from disk in any browser (no
server, no network, nothing fetched), with the numbers beside it for a program.

The report folder holds:
- `index.html`: the runs, their learning curves, the latest evaluation as a table with each level's picture and
  a GIF of the agent playing it, the top of the curriculum buffer (runs with one), the resolved config and the
  library versions;
- `report.json` (`kinetix-report/1`): what the page shows, as numbers; `curves.json` (`kinetix-curves/1`);
- `curves.png`, `levels/<k>.png`, `episodes/<group>-<k>.gif`, `buffers/<run>.png`.

Several runs are grouped as `kinetix plot` groups them (runs differing only in seed are one group, or by
`--group` keys): the evaluation table has one column per group (the mean over its runs, with their min..max),
and each group's agent (its first run, at the evaluated checkpoint) plays the GIFs. A run's latest evaluation is
its newest `evaluations/<update>.json` (written during training), or a `kinetix eval --json` file given for it.
"""

from __future__ import annotations

import dataclasses
import html
import json
import math
from collections.abc import Callable
from pathlib import Path

import jax
import numpy as np

from kinetix_cli.constants import CURVES_FORMAT, REPORT_FORMAT, VERSIONS_FORMAT
from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_folder, atomic_write_json, atomic_write_text, check_output_dir, read_format
from kinetix_cli.levels.files import load_level
from kinetix_cli.provenance import environment_info
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.checkpoints import CHECKPOINTS
from kinetix_cli.rl.evaluate import read_evaluation
from kinetix_cli.rl.record import EVALUATIONS, VERSIONS_FILE
from kinetix_cli.viz.buffer import buffer_levels
from kinetix_cli.viz.contact_sheet import contact_sheet
from kinetix_cli.viz.curves import (
    CONFIG_FILE,
    Run,
    draw,
    group_runs,
    learning_curves,
    metrics_of,
    read_run,
    save_figure,
)
from kinetix_cli.viz.render import render_level, save_gif, save_png
from kinetix_cli.viz.rollout import episode_frames, record_episodes

CURVE_METRICS = ("eval_solve_rate", "solve_rate", "return", "buffer_solve_rate")
"""The metrics drawn, those the runs logged, in this order."""
LEVEL_SCALE = 40
"""Pixels per metre of the level pictures and GIFs."""
BUFFER_TOP = 16
"""Buffer levels drawn per run (best first)."""
PAGE_FILE, DATA_FILE = "index.html", "report.json"
REPORT_FILES = (PAGE_FILE, DATA_FILE)
"""What makes a folder a report (one `kinetix report` may replace)."""


@dataclasses.dataclass
class Group:
    """Runs of one experiment (see `curves.group_runs`) with their evaluations (None: the run has none)."""

    label: str
    runs: list[Run]
    evaluations: list[tuple[Path, dict] | None]

    @property
    def evaluated(self) -> list[tuple[Path, dict]]:
        return [e for e in self.evaluations if e is not None]


def latest_evaluation(run: Path) -> Path | None:
    """The newest evaluation training wrote in `run` (`evaluations/<update>.json`), or None."""
    folder = run / EVALUATIONS
    files = [f for f in folder.glob("*.json") if f.stem.isdigit()] if folder.is_dir() else []
    return max(files, key=lambda f: int(f.stem), default=None)


def write_report(
    paths: list[Path],
    out: Path,
    *,
    group_by: list[str] | None = None,
    evaluations: list[Path] | None = None,
    gifs: bool = True,
    progress: Callable[[str], None] = lambda line: None,
) -> dict:
    """Write the report of the runs `paths` into the folder `out` (whole or not at all; an earlier report there is
    replaced, any other non-empty folder refused) and return its `report.json` payload. `evaluations`: one
    `kinetix eval --json` file per run, in the order of `paths`, instead of the runs' own latest ones."""
    out = check_output_dir(out, "-o")
    if out.is_dir() and any(out.iterdir()) and not all((out / f).is_file() for f in REPORT_FILES):
        raise UserError(f"-o {out}: not empty and not a report folder; choose a new folder")
    runs = [read_run(Path(p)) for p in paths]
    if evaluations is not None and len(evaluations) != len(runs):
        raise UserError(f"--eval: give one eval file per run ({len(runs)} runs, {len(evaluations)} files)")
    chosen = evaluations or [latest_evaluation(run.path) for run in runs]
    by_run = {run.path: (file, read_evaluation(file)) if file else None for run, file in zip(runs, chosen, strict=True)}
    groups = [
        Group(label, members, [by_run[r.path] for r in members])
        for label, members in group_runs(runs, group_by).items()
    ]
    with atomic_folder(out, "-o") as folder:
        notes: list[str] = []
        progress("report: learning curves")
        curves = _curves(runs, group_by, folder, notes)
        levels = _levels(groups)
        progress(f"report: {len(levels)} evaluated levels")
        pictures = _level_pictures(levels, folder, notes)
        episodes = _episodes(groups, levels, folder, notes, progress) if gifs else {}
        progress("report: curriculum buffers")
        buffers = _buffers(runs, folder, notes)
        payload = {
            "runs": [_run_entry(run, groups, by_run[run.path]) for run in runs],
            "groups": [group.label for group in groups],
            "curves": curves,
            "levels": [
                {
                    "level": level,
                    "suite": suite,
                    "picture": pictures.get(level),
                    "solve_rates": {g.label: _rates(g, level) for g in groups},
                    "episodes": episodes.get(level, {}),
                }
                for level, suite in levels
            ],
            "buffers": buffers,
            "notes": notes,
            "made_with": environment_info(),
        }
        atomic_write_json(folder / DATA_FILE, payload, REPORT_FORMAT)
        atomic_write_text(folder / PAGE_FILE, _page(runs, groups, payload))
    return payload


def _curves(runs: list[Run], group_by, folder: Path, notes: list[str]) -> str | None:
    """curves.png and curves.json of the metrics the runs logged; None (and a note) when they logged nothing."""
    metrics = [m for m in CURVE_METRICS if m in metrics_of(runs)]
    if not metrics:
        notes.append("no learning curves: the runs have not logged an update yet")
        return None
    curves = learning_curves([run.path for run in runs], metrics, "steps", group_by)
    save_figure(draw(curves, "steps"), folder / "curves.png")
    points = [row for c in curves for row in c.rows()]
    atomic_write_json(folder / "curves.json", {"x": "steps", "points": points}, CURVES_FORMAT)
    return "curves.png"


def _levels(groups: list[Group]) -> list[tuple[str, str]]:
    """(level file, suite) of every evaluated level, in first-seen order."""
    seen: dict[str, str] = {}
    for group in groups:
        for _, payload in group.evaluated:
            for entry in payload["levels"]:
                seen.setdefault(str(entry["level"]), str(entry["suite"]))
    return list(seen.items())


def _rates(group: Group, level: str) -> dict:
    """The group's solve rate of `level`: mean, min and max over its runs that evaluated it, and each run's."""
    rates = [
        float(entry["solve_rate"])
        for _, payload in group.evaluated
        for entry in payload["levels"]
        if str(entry["level"]) == level
    ]
    if not rates:
        return {"mean": None, "min": None, "max": None, "runs": []}
    return {"mean": float(np.mean(rates)), "min": min(rates), "max": max(rates), "runs": rates}


def _level_pictures(levels: list[tuple[str, str]], folder: Path, notes: list[str]) -> dict[str, str]:
    """levels/<k>.png of each evaluated level file that can be read now."""
    pictures = {}
    for k, (level, _) in enumerate(levels):
        if not Path(level).is_file():
            notes.append(f"{level}: level file not found from here; no picture or GIF")
            continue
        spec = load_level(Path(level))
        pictures[level] = f"levels/{k}.png"
        save_png(render_level(spec.build(), scale=LEVEL_SCALE, title=spec.name), folder / pictures[level])
    return pictures


def _episodes(groups, levels, folder: Path, notes: list[str], progress) -> dict[str, dict[str, dict]]:
    """episodes/<g>-<k>.gif: each group's agent (its first evaluated run, at the evaluated checkpoint) playing each
    level it was evaluated on, one episode (seed 0, actions sampled); level -> group -> the episode's entry."""
    episodes: dict[str, dict[str, dict]] = {}
    index = {level: k for k, (level, _) in enumerate(levels)}
    for g, group in enumerate(groups):
        evaluated = [(run, e) for run, e in zip(group.runs, group.evaluations, strict=True) if e is not None]
        if not evaluated:
            continue
        run, (_, payload) = evaluated[0]
        if not (run.path / CHECKPOINTS).is_dir():
            notes.append(f"{run.path}: no checkpoint yet; no GIFs of {group.label}'s agent")
            continue
        source = _checkpoint_of(run.path, payload.get("update"))
        policy = load_policy(source)
        files = [str(e["level"]) for e in payload["levels"] if Path(str(e["level"])).is_file()]
        by_size: dict[str, list] = {}
        for file in files:
            spec = load_level(Path(file))
            by_size.setdefault(spec.default_size(), []).append((file, spec))
        for size, entries in by_size.items():
            progress(f"report: {group.label}: playing {len(entries)} size-{size} levels (update {policy.update})")
            env, env_params = policy.env_for(size, entries[0][0])
            keys = jax.random.split(jax.random.key(0), len(entries))
            built = [spec.build(env.static) for _, spec in entries]
            played = record_episodes(env, env_params, built, policy.act, keys, policy.config.env.max_steps)
            for (file, spec), episode in zip(entries, played, strict=True):
                gif = f"episodes/{g}-{index[file]}.gif"
                every = max(1, math.ceil(episode.length / 200))  # at most ~200 frames per GIF
                frames = episode_frames(spec.name, episode, scale=LEVEL_SCALE, every=every)
                save_gif(frames, folder / gif, fps=1.0 / (episode.step_seconds * every))
                episodes.setdefault(file, {})[group.label] = {
                    "gif": gif,
                    "policy": str(source),
                    "update": policy.update,
                    "ending": episode.ending,
                    "return": episode.total_return,
                    "length": episode.length,
                }
    return episodes


def _checkpoint_of(run: Path, update) -> Path:
    """The checkpoint an evaluation played (when still kept), else the run's latest."""
    folder = run / CHECKPOINTS / str(update)
    return folder if isinstance(update, int) and folder.is_dir() else run


def _buffers(runs: list[Run], folder: Path, notes: list[str]) -> list[dict]:
    """buffers/<r>.png: the top of each curriculum run's buffer at its latest checkpoint."""
    buffers = []
    for r, run in enumerate(runs):
        if run.settings.get("curriculum.name", "dr") == "dr":
            continue
        if not (run.path / CHECKPOINTS).is_dir():
            notes.append(f"{run.path}: no checkpoint yet; no buffer to draw")
            continue
        levels = buffer_levels(run.path, 0, BUFFER_TOP)
        if not levels:
            notes.append(f"{run.path}: the curriculum buffer is empty at the latest checkpoint")
            continue
        image = f"buffers/{r}.png"
        save_png(contact_sheet(levels, columns=math.ceil(math.sqrt(len(levels))), scale=30), folder / image)
        buffers.append({"run": str(run.path), "image": image, "levels": len(levels)})
    return buffers


def _run_entry(run: Run, groups: list[Group], evaluation: tuple[Path, dict] | None) -> dict:
    lines = run.lines
    return {
        "path": str(run.path),
        "group": next(g.label for g in groups if any(member is run for member in g.runs)),
        "seed": run.settings.get("run.seed"),
        "curriculum": run.settings.get("curriculum.name"),
        "init_from": run.settings.get("run.init_from"),
        "updates": lines[-1].get("update", len(lines)) if lines else 0,
        "steps": lines[-1].get("total_steps", lines[-1].get("steps")) if lines else 0,
        "evaluation": None
        if evaluation is None
        else {"file": str(evaluation[0]), "update": evaluation[1].get("update")},
    }


# --- the page ----------------------------------------------------------------------------------------------------

STYLE = """
body { font: 14px/1.45 system-ui, sans-serif; margin: 2em auto; max-width: 1200px; padding: 0 1em; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; margin-top: 2em; border-bottom: 1px solid #ddd; }
table { border-collapse: collapse; margin: 0.5em 0; } td, th { border: 1px solid #ddd; padding: 4px 8px; }
th { background: #f4f4f4; text-align: left; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
img { max-width: 100%; } pre { background: #f8f8f8; padding: 1em; overflow-x: auto; }
.small { color: #666; font-size: 0.85em; } .note { color: #8a5a00; } .wide { overflow-x: auto; }
"""


def _e(value) -> str:
    return html.escape(str(value))


def _table(header: list[str], rows: list[list[str]]) -> str:
    """An HTML table; cells are HTML already (escape text before)."""
    head = "".join(f"<th>{h}</th>" for h in header)
    body = "".join("<tr>" + "".join(row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _td(text: str, numeric: bool = False) -> str:
    return f'<td class="num">{text}</td>' if numeric else f"<td>{text}</td>"


def _percent(rate: dict) -> str:
    if rate["mean"] is None:
        return "-"
    spread = f' <span class="small">({100 * rate["min"]:.0f}..{100 * rate["max"]:.0f})</span>'
    return f"{100 * rate['mean']:.1f}%" + (spread if len(rate["runs"]) > 1 else "")


def _page(runs: list[Run], groups: list[Group], payload: dict) -> str:
    names = ", ".join(run.path.name for run in runs)
    made = payload["made_with"]
    parts = [
        f"<h1>kinetix report: {_e(names)}</h1>",
        f'<p class="small">made {_e(made["date"])} by kinetix {_e(made["versions"]["kinetix"])}</p>',
        "<h2>Runs</h2>",
        _table(
            ["run", "group", "seed", "curriculum", "started from", "updates", "env steps", "evaluation"],
            [
                [
                    _td(_e(r["path"])),
                    _td(_e(r["group"])),
                    _td(_e(r["seed"]), True),
                    _td(_e(r["curriculum"])),
                    _td(_e(r["init_from"] or "scratch")),
                    _td(f"{r['updates']:,}", True),
                    _td(f"{r['steps']:,}", True),
                    _td(_e("none" if r["evaluation"] is None else r["evaluation"]["file"])),
                ]
                for r in payload["runs"]
            ],
        ),
        "<h2>Learning curves</h2>",
        (
            f'<img src="{payload["curves"]}" alt="learning curves"><p class="small">mean over each group\'s runs, '
            'shaded min..max; the numbers: <a href="curves.json">curves.json</a></p>'
            if payload["curves"]
            else "<p>none yet</p>"
        ),
        "<h2>Latest evaluation</h2>",
        _evaluation_section(groups, payload),
    ]
    if payload["buffers"]:
        parts.append("<h2>Curriculum buffer (top levels, highest score first)</h2>")
        for b in payload["buffers"]:
            parts.append(f'<p>{_e(b["run"])}: {b["levels"]} levels</p><img src="{b["image"]}" alt="buffer">')
    parts += ["<h2>Config</h2>", _config_section(runs), "<h2>Versions</h2>", _versions_section(runs)]
    if payload["notes"]:
        parts += [
            "<h2>Notes</h2>",
            "<ul>" + "".join(f'<li class="note">{_e(n)}</li>' for n in payload["notes"]) + "</ul>",
        ]
    body = "\n".join(parts)
    return (
        f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n<title>kinetix report: {_e(names)}'
        f"</title>\n<style>{STYLE}</style>\n</head>\n<body>\n{body}\n</body>\n</html>\n"
    )


def _evaluation_section(groups: list[Group], payload: dict) -> str:
    if not payload["levels"]:
        return (
            "<p>No evaluation: these runs evaluate nothing during training (run.eval_every or run.eval_levels). "
            "Run <code>kinetix eval RUN --levels ... --json FILE</code> and pass <code>--eval FILE</code>.</p>"
        )
    sources = []
    for group in groups:
        for run, evaluation in zip(group.runs, group.evaluations, strict=True):
            if evaluation is not None:
                file, record = evaluation
                sources.append(
                    f"<li>{_e(run.path.name)}: {_e(file)} (update {_e(record.get('update'))}, "
                    f"{_e(record.get('attempts'))} attempts per level)</li>"
                )
    labels = [g.label for g in groups]
    header = ["level", "suite", *(f"solve rate: {_e(_name(g))}" for g in groups)]
    header += [f"agent: {_e(g.label)}" for g in groups]
    rows = []
    for entry in payload["levels"]:
        picture = entry["picture"]
        cell = f'<img src="{picture}" alt="{_e(entry["level"])}" width="200"><br>' if picture else ""
        row = [_td(f'{cell}<span class="small">{_e(entry["level"])}</span>'), _td(_e(entry["suite"]))]
        row += [_td(_percent(entry["solve_rates"][label]), True) for label in labels]
        for label in labels:
            episode = entry["episodes"].get(label)
            row.append(
                _td(
                    f'<img src="{episode["gif"]}" alt="agent playing" width="200"><br><span class="small">'
                    f"{_e(episode['ending'])} after {episode['length']} steps, return {episode['return']:+.2f}</span>"
                    if episode
                    else "-"
                )
            )
        rows.append(row)
    means = []
    for label in labels:
        rates = [e["solve_rates"][label]["mean"] for e in payload["levels"]]
        rates = [r for r in rates if r is not None]
        means.append(_td(f"<b>{100 * float(np.mean(rates)):.1f}%</b>" if rates else "-", True))
    rows.append([_td("<b>mean over levels</b>"), _td("")] + means + [_td("") for _ in labels])
    return (
        f"<ul>{''.join(sources)}</ul>"
        + f'<div class="wide">{_table(header, rows)}</div>'
        + (
            '<p class="small">solve rate: mean over the group\'s runs (min..max over runs); each GIF is one episode '
            "(seed 0) of the group's first run</p>"
        )
    )


def _name(group: Group) -> str:
    """A group's label, with its number of runs when several."""
    return f"{group.label} ({len(group.runs)} runs)" if len(group.runs) > 1 else group.label


def _config_section(runs: list[Run]) -> str:
    text = (runs[0].path / CONFIG_FILE).read_text(encoding="utf-8")
    parts = [f"<p>{_e(runs[0].path / CONFIG_FILE)}</p><pre>{_e(text)}</pre>"]
    keys = sorted(
        k for k in set().union(*(r.settings for r in runs)) if len({json.dumps(r.settings.get(k)) for r in runs}) > 1
    )
    if keys:
        rows = [[_td(_e(run.path))] + [_td(_e(run.settings.get(k))) for k in keys] for run in runs]
        parts.insert(0, "<p>Settings that differ between the runs:</p>" + _table(["run", *map(_e, keys)], rows))
    return "".join(parts)


def _versions_section(runs: list[Run]) -> str:
    rows = []
    for run in runs:
        file = run.path / VERSIONS_FILE
        try:
            info = read_format(file, VERSIONS_FORMAT, UserError)
        except UserError as exc:
            rows.append([_td(_e(run.path)), _td(_e(f"unreadable: {exc}")), _td(""), _td("")])
            continue
        versions = ", ".join(f"{k} {v}" for k, v in info.get("versions", {}).items())
        machine = ", ".join(f"{v}" for v in info.get("machine", {}).values())
        rows.append([_td(_e(run.path)), _td(_e(info.get("date"))), _td(_e(machine)), _td(_e(versions))])
    return _table(["run", "started", "machine", "versions"], rows)
