"""Procedurally generated level sets on disk, written by a resumable driver and read back verified.

A level set is a directory: `manifest.json` (format `kinetix-levelset/1`) and shards `shard-00000.npz`, ...,
each holding a batch of levels of one size as one array per leaf of the levels' `physics` and `bindings`, keyed
by its tree path ("physics/bodies/position": (n, num_bodies, 2) float32). Every shard but the last holds
`shard_size` levels. A *solved* set (manifest `"solutions": true`, written by `kinetix levels solve`) also holds each
level's solution search result: "solution/actions" (n, 256, 6) int8 multi-discrete actions, "solution/solved" (n,)
bool (False: no search solved it, and the actions are no-ops) and "solution/length" (n,) int32 steps to the solve.
Generated levels run with the engine's default constants, so `engine_params` is not stored; loaded levels carry the
defaults.
While generating, `progress.json` records where to resume; it is removed once the manifest is written.
Files are byte-reproducible: the same call always writes the same bytes, interrupted or not, in one process or
several: in a multi-process run (`kinetix_cli.parallel`) every process computes every chunk together (split over
all devices) and keeps the same account of the set, shard k is written by process k mod P, and process 0 writes
`progress.json` and the manifest once every process has written its shards (the folder must be shared).
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import os
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

import jax
import numpy as np

from engine import SIZES, Scene
from kinetix_cli.config import EnvSettings
from kinetix_cli.constants import ACTION_WIDTH, LEVELSET_FORMAT, LEVELSET_PROGRESS_FORMAT
from kinetix_cli.env.level import Level, empty_bindings, index_level, make_level
from kinetix_cli.errors import UserError, WriteError
from kinetix_cli.io import atomic_write, atomic_write_json, check_output_dir, read_format
from kinetix_cli.parallel import is_primary, process_count, process_index, sync
from kinetix_cli.provenance import tool_version

PROGRESS_FORMAT = LEVELSET_PROGRESS_FORMAT
MANIFEST_FILE = "manifest.json"
PROGRESS_FILE = "progress.json"
SHARD_FILE = "shard-{:05d}.npz"
DEFAULT_SHARD_SIZE = 4096
ZIP_DATE_TIME = (1980, 1, 1, 0, 0, 0)
"""Fixed zip member time stamp (the earliest zip allows), so shards are byte-reproducible."""
IDENTITY_FIELDS = ("size", "count", "seed", "shard_size", "settings")
"""Arguments that define a set: resuming or re-running with a different value is refused."""
MAX_IDLE_CHUNKS = 50
"""Generation stops with an error after this many chunks in a row add no level (filters too strict)."""

Arrays = dict[str, np.ndarray]
"""A batch of levels as leaf path -> (n, *leaf shape) array, in the tree's leaf order."""


@dataclasses.dataclass
class Solutions:
    """The solutions of a batch of levels (numpy, leading axis = level).

    Attributes:
        actions: (n, SOLUTION_STEPS, 6) int8 multi-discrete actions (no-ops after the solve, and for unsolved levels).
        solved: (n,) bool, whether `actions` solve the level.
        length: (n,) int32 environment steps to the solve (0 when unsolved).
    """

    actions: np.ndarray
    solved: np.ndarray
    length: np.ndarray


@dataclasses.dataclass
class LevelSet:
    """A loaded level set: `manifest` as written, `levels` a batched `Level` of numpy (count, ...) arrays, and for a
    solved set its `solutions`."""

    manifest: dict
    levels: Level
    solutions: Solutions | None = None


@dataclasses.dataclass
class _Run:
    """The driver's carry: where the next level comes from and what has been kept so far.

    `stats` holds the counters of chunks < `next_chunk`, and of chunk `next_chunk` too when `offset` > 0.
    `pending` holds kept levels not yet in a shard (fewer than a shard); `hashes` all kept level digests;
    `recorded` the shards that `progress.json` names (what a resumed run keeps).
    """

    next_chunk: int = 0
    offset: int = 0
    stats: dict = dataclasses.field(default_factory=lambda: {"duplicates": 0})
    shards: list = dataclasses.field(default_factory=list)
    hashes: set = dataclasses.field(default_factory=set)
    pending: list = dataclasses.field(default_factory=list)
    kept: int = 0
    recorded: list = dataclasses.field(default_factory=list)


def template_level(size: str) -> Level:
    """One empty (arena-only) level of `size` with numpy leaves: the leaf paths, shapes and dtypes of a set."""
    static = SIZES[size]
    return make_level(Scene().build_numpy(static), empty_bindings(static.num_joints, static.num_thrusters))


STORED_FIELDS = ("physics", "bindings")
"""The parts of a `Level` a level set stores, in this order."""
SOLUTION_STEPS = EnvSettings.max_steps
"""Steps of a stored solution: the episode cap solutions are recorded at (`levels.solution.SOLUTION_SETTINGS`)."""
SOLUTION_ARRAYS = {
    "solution/actions": np.zeros((SOLUTION_STEPS, ACTION_WIDTH), np.int8),
    "solution/solved": np.zeros((), bool),
    "solution/length": np.zeros((), np.int32),
}
"""The leaves a solved set adds after the level's, with one level's shape and dtype."""


def template_arrays(size: str, solutions: bool = False) -> Arrays:
    """One level's leaves (and a solved set's solution leaves) as a set of `size` stores them."""
    return to_arrays(template_level(size)) | (SOLUTION_ARRAYS if solutions else {})


def solution_arrays(solutions: Solutions) -> Arrays:
    """The solved set's leaves of a batch of solutions."""
    return {
        "solution/actions": np.asarray(solutions.actions, np.int8),
        "solution/solved": np.asarray(solutions.solved, bool),
        "solution/length": np.asarray(solutions.length, np.int32),
    }


def to_arrays(levels: Level) -> Arrays:
    """Flatten the stored parts of a batched level into leaf path ("physics/bodies/position") -> numpy array."""
    arrays = {}
    for part in STORED_FIELDS:
        for path, x in jax.tree_util.tree_flatten_with_path(getattr(levels, part))[0]:
            arrays["/".join([part, *(k.name for k in path)])] = np.asarray(x)
    return arrays


def from_arrays(arrays: Arrays, template: Level) -> Level:
    """Inverse of `to_arrays`, with the tree structure of `template`; the levels get the default engine constants."""
    leaves, parts = iter(arrays.values()), {}
    for part in STORED_FIELDS:
        structure = jax.tree.structure(getattr(template, part))
        parts[part] = jax.tree.unflatten(structure, [next(leaves) for _ in range(structure.num_leaves)])
    count = _rows(arrays)
    params = jax.tree.map(lambda x: np.full(count, x, np.float32), template.engine_params)
    return Level(parts["physics"], parts["bindings"], params)


def _rows(arrays: Arrays) -> int:
    return len(next(iter(arrays.values())))


def level_digests(arrays: Arrays) -> list[bytes]:
    """The content hash of each level: sha256 (32 bytes) of all its leaf bytes, in leaf order. Returns n."""
    n = _rows(arrays)
    if n == 0:
        return []
    rows = np.concatenate([np.ascontiguousarray(x).reshape(n, -1).view(np.uint8) for x in arrays.values()], axis=1)
    return [hashlib.sha256(row.tobytes()).digest() for row in rows]


def shape_problem(arrays: Arrays, template: Arrays) -> str | None:
    """Why `arrays` is not a batch shaped like `template` (keys, dtypes, equal leading axis), or None."""
    if set(arrays) != set(template):
        return f"leaves {sorted(set(arrays) ^ set(template))} missing or unexpected"
    n = _rows(arrays)
    for key in template:
        x = arrays[key]
        if x.shape != (n, *template[key].shape) or x.dtype != template[key].dtype:
            return f"{key}: {x.dtype}{list(x.shape)}, expected {template[key].dtype}{[n, *template[key].shape]}"
    return None


def write_npz(f: BinaryIO, arrays: Arrays) -> None:
    """Write `arrays` as an uncompressed .npz (readable by `np.load`) with fixed time stamps."""
    with zipfile.ZipFile(f, "w", zipfile.ZIP_STORED) as zf:
        for key, x in arrays.items():
            info = zipfile.ZipInfo(f"{key}.npy", date_time=ZIP_DATE_TIME)
            info.external_attr = 0o644 << 16
            with zf.open(info, "w", force_zip64=True) as member:
                np.lib.format.write_array(member, np.ascontiguousarray(x), allow_pickle=False)


def read_shard(path: Path, entry: dict, template: Arrays) -> Arrays:
    """Read and verify one shard (sha256, leaves, shapes, count) against its manifest `entry`."""
    if not path.is_file():
        raise UserError(f"{path}: shard missing")
    data = path.read_bytes()
    if hashlib.sha256(data).hexdigest() != entry["sha256"]:
        raise UserError(f"{path}: sha256 does not match the manifest (corrupted or truncated shard)")
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as npz:
            arrays = {key: npz[key] for key in npz.files}
    except (zipfile.BadZipFile, ValueError, OSError, EOFError, KeyError) as e:
        raise UserError(f"{path}: not a readable .npz ({e})") from None
    problem = shape_problem(arrays, template) if arrays else "no arrays"
    if problem is None and _rows(arrays) != entry["count"]:
        problem = f"{_rows(arrays)} levels, manifest says count={entry['count']}"
    if problem:
        raise UserError(f"{path}: {problem}")
    return {key: arrays[key] for key in template}


def generate_levelset(
    out_dir: str | os.PathLike,
    *,
    size: str,
    count: int,
    seed: int,
    settings: dict,
    chunk_fn: Callable[[int], tuple],
    shard_size: int = DEFAULT_SHARD_SIZE,
    progress: Callable[[int, dict], None] | None = None,
    solutions: bool = False,
) -> dict:
    """Generate (or resume, or return the finished) level set in `out_dir`; returns its manifest.

    `chunk_fn(i)` returns chunk i's kept levels (a batched `Level`, (n, ...) leaves, n may be 0) and its
    counters (e.g. {"sampled": 64, "dropped_noop": 3}), and with `solutions` (a solved set) also their
    `Solutions`; it must be deterministic in i. Chunks 0, 1, ... are
    consumed in order, levels already kept (same content hash) are dropped and counted in
    stats["duplicates"], until `count` levels are kept. Shards are written as they fill; memory holds about
    one shard plus one chunk. `progress(kept, stats)` is called after each chunk with the summed counters.
    """
    out = check_output_dir(out_dir, "--out")
    if size not in SIZES:
        raise UserError(f"--size: unknown size {size!r}; choose one of {', '.join(SIZES)}")
    if count < 1 or shard_size < 1:
        raise UserError(f"--count and --shard-size must be >= 1, got {count} and {shard_size}")
    identity = json.loads(json.dumps(dict(size=size, count=count, seed=seed, shard_size=shard_size, settings=settings)))
    if solutions:
        identity["solutions"] = True
    template = template_arrays(size, solutions)
    _remove_temporaries(out)
    if (out / MANIFEST_FILE).is_file():
        manifest = read_format(out / MANIFEST_FILE, LEVELSET_FORMAT)
        _check_identity(out, manifest, identity)
        _check_manifest(out / MANIFEST_FILE, manifest)
        for entry in manifest["shards"]:  # a finished set is only reported as written if its bytes are intact
            read_shard(out / entry["file"], entry, template)
        (out / PROGRESS_FILE).unlink(missing_ok=True)  # left by a crash just after the manifest was written
        return manifest
    run = _resume(out, identity, template)
    sync("levelset checked")  # every process has read the folder before the primary writes to it
    try:
        if not (out / PROGRESS_FILE).is_file():
            _save_progress(out, run, identity)
        return _generate(out, run, count, identity, chunk_fn, template, progress)
    except WriteError as exc:
        kept = sum(shard["count"] for shard in run.recorded)
        raise WriteError(
            f"{exc}; the {kept:,} levels of the {len(run.recorded)} complete shards are kept; once the folder can "
            "be written, rerun the same command to continue"
        ) from None


def _generate(out: Path, run: _Run, count: int, identity: dict, chunk_fn, template: Arrays, progress) -> dict:
    """`generate_levelset`'s loop: chunks until `count` levels are kept, then the manifest."""
    idle = 0  # chunks in a row that added no level
    while run.kept < count:
        i, (arrays, chunk_stats) = run.next_chunk, _chunk(chunk_fn, run.next_chunk, template)
        if run.offset == 0:
            for key, value in chunk_stats.items():
                run.stats[key] = run.stats.get(key, 0) + int(value)
        before = run.kept
        _consume(out, run, i, arrays, identity)
        idle = 0 if run.kept > before else idle + 1
        if idle >= MAX_IDLE_CHUNKS:
            raise UserError(
                f"{out}: {MAX_IDLE_CHUNKS} chunks in a row kept no new level ({dict(run.stats)}); loosen --filter"
            )
        if progress is not None:
            progress(run.kept, dict(run.stats))
    manifest = dict(identity, version=tool_version(), shards=run.shards, stats=dict(sorted(run.stats.items())))
    if is_primary():
        atomic_write_json(out / MANIFEST_FILE, manifest, LEVELSET_FORMAT)
        (out / PROGRESS_FILE).unlink()
    sync("levelset written")
    return {"format": LEVELSET_FORMAT, **manifest}


def _remove_temporaries(out: Path) -> None:
    """Remove the temporary files a killed write left in a set's folder (`.<name>.*.tmp`, see `io.atomic_write`)."""
    if out.is_dir():
        for stale in out.glob(".*.tmp"):
            stale.unlink(missing_ok=True)


def _chunk(chunk_fn: Callable, i: int, template: Arrays) -> tuple[Arrays, dict]:
    levels, stats, *solved = chunk_fn(i)
    arrays = to_arrays(levels) | (solution_arrays(solved[0]) if solved else {})
    if problem := shape_problem(arrays, template):
        raise ValueError(f"chunk_fn({i}) returned levels of the wrong shape: {problem}")
    return arrays, stats


def _consume(out: Path, run: _Run, i: int, arrays: Arrays, identity: dict) -> None:
    """Keep chunk i's new levels from row `run.offset` on, writing a shard each time one fills."""
    n, keep, room = _rows(arrays), [], identity["shard_size"] - sum(map(_rows, run.pending))
    for row, digest in enumerate(level_digests(arrays)[run.offset :], start=run.offset):
        if digest in run.hashes:
            run.stats["duplicates"] += 1
            continue
        run.hashes.add(digest)
        keep.append(row)
        run.kept += 1
        if len(keep) == room or run.kept == identity["count"]:
            run.pending.append({key: x[keep] for key, x in arrays.items()})
            keep, room = [], identity["shard_size"]
            run.next_chunk, run.offset = (i, row + 1) if row + 1 < n else (i + 1, 0)
            _write_shard(out, run, identity)
            if run.kept == identity["count"]:
                return
    run.pending.append({key: x[keep] for key, x in arrays.items()})
    run.next_chunk, run.offset = i + 1, 0


def _write_shard(out: Path, run: _Run, identity: dict) -> None:
    """Write the pending levels as the next shard, then record progress."""
    arrays = {key: np.concatenate([p[key] for p in run.pending]) for key in run.pending[0]}
    buffer = io.BytesIO()
    write_npz(buffer, arrays)
    name = SHARD_FILE.format(len(run.shards))
    if len(run.shards) % process_count() == process_index():  # one process writes each shard
        atomic_write(out / name, lambda f: f.write(buffer.getvalue()))
    run.shards.append({"file": name, "count": _rows(arrays), "sha256": hashlib.sha256(buffer.getvalue()).hexdigest()})
    run.pending = []
    sync(f"levelset {name}")  # the shard is on disk before progress names it
    _save_progress(out, run, identity)


def _save_progress(out: Path, run: _Run, identity: dict) -> None:
    """Record where to resume (the primary process writes it); its shards are then kept for good."""
    if is_primary():
        fields = {"next_chunk": run.next_chunk, "offset": run.offset, "stats": run.stats, "shards": run.shards}
        atomic_write_json(out / PROGRESS_FILE, dict(identity, **fields), PROGRESS_FORMAT)
    run.recorded = list(run.shards)


def _resume(out: Path, identity: dict, template: Arrays) -> _Run:
    """A fresh run in an empty or new `out`, or the run recorded in its progress file (shards re-verified)."""
    if not (out / PROGRESS_FILE).is_file():
        if out.exists() and any(out.iterdir()):
            raise UserError(f"{out}: not empty and not a level set; choose a new or empty directory")
        return _Run()
    saved = read_format(out / PROGRESS_FILE, PROGRESS_FORMAT)
    _check_identity(out, saved, identity)
    try:
        run = _Run(saved["next_chunk"], saved["offset"], saved["stats"], saved["shards"])
    except KeyError as e:
        raise UserError(f"{out / PROGRESS_FILE}: {e.args[0]}: missing; delete the directory to start over") from None
    file = out / PROGRESS_FILE
    for field, value in (("next_chunk", run.next_chunk), ("offset", run.offset)):
        if not isinstance(value, int) or isinstance(value, bool) or value < 0:
            raise UserError(f"{file}: {field}: expected an integer >= 0; delete the directory to start over")
    if not isinstance(run.stats, dict):
        raise UserError(f"{file}: stats: expected an object; delete the directory to start over")
    _check_shards(file, run.shards, allow_empty=True)
    for entry in run.shards:
        run.hashes.update(level_digests(read_shard(out / entry["file"], entry, template)))
        run.kept += entry["count"]
    run.recorded = list(run.shards)
    return run


def _check_identity(out: Path, recorded: dict, identity: dict) -> None:
    for key in (*IDENTITY_FIELDS, "solutions"):
        if recorded.get(key) != identity.get(key):
            raise UserError(
                f"{out}: holds a level set with {key}={recorded.get(key)!r}, not {identity.get(key)!r}; "
                "use another directory or delete this one"
            )


def load_levelset(path: str | os.PathLike) -> LevelSet:
    """Load and verify a finished level set: manifest fields, each shard's sha256, leaves and counts."""
    root = Path(path)
    file = root / MANIFEST_FILE
    if not file.is_file():
        unfinished = " (generation unfinished: run it again to resume)" if (root / PROGRESS_FILE).exists() else ""
        raise UserError(f"{file}: not found{unfinished}")
    manifest = read_format(file, LEVELSET_FORMAT)
    _check_manifest(file, manifest)
    template_tree = template_level(manifest["size"])
    solved = manifest.get("solutions", False)
    template = template_arrays(manifest["size"], solved)
    parts = [read_shard(root / entry["file"], entry, template) for entry in manifest["shards"]]
    arrays = {key: np.concatenate([p[key] for p in parts]) for key in template}
    solutions = None
    if solved:
        solutions = Solutions(*(arrays.pop(key) for key in SOLUTION_ARRAYS))
    return LevelSet(manifest, from_arrays(arrays, template_tree), solutions)


def _check_manifest(file: Path, manifest: dict) -> None:
    """Raise a UserError naming the first bad manifest field."""

    def bad(field: str, problem: str):
        raise UserError(f"{file}: {field}: {problem}")

    if manifest.get("size") not in SIZES:
        bad("size", f"expected one of {', '.join(SIZES)}, got {manifest.get('size')!r}")
    if not isinstance(manifest.get("solutions", False), bool):
        bad("solutions", "expected true or false")
    for field, kind in (("seed", int), ("stats", dict), ("settings", dict)):
        if not isinstance(manifest.get(field), kind) or isinstance(manifest.get(field), bool):
            bad(field, f"missing or not {'an integer' if kind is int else 'an object'}")
    shards = manifest.get("shards")
    _check_shards(file, shards, allow_empty=False)
    if not isinstance(manifest.get("count"), int) or manifest["count"] != sum(e["count"] for e in shards):
        bad("count", f"{manifest.get('count')!r} is not the sum of the shard counts")


def _check_shards(file: Path, shards, allow_empty: bool) -> None:
    """Raise a UserError unless `shards` is a list of {file: a plain file name, count: int, sha256: str}."""
    if not isinstance(shards, list) or not (shards or allow_empty):
        raise UserError(f"{file}: shards: expected a {'' if allow_empty else 'non-empty '}list of shard entries")
    for k, entry in enumerate(shards):
        ok = isinstance(entry, dict) and isinstance(entry.get("count"), int) and isinstance(entry.get("sha256"), str)
        if not ok or not isinstance(entry.get("file"), str) or Path(entry["file"]).name != entry["file"]:
            raise UserError(f"{file}: shards[{k}]: expected {{file: a plain file name, count: int, sha256: str}}")


def solved_rows(levelset: LevelSet, path: str | os.PathLike, field: str) -> np.ndarray:
    """The indices of the levels a solved set's search solved; a UserError naming `field` (the config field that
    named the set at `path`) if the set holds no solutions or none is solved."""
    if levelset.solutions is None:
        raise UserError(f"{field}: {path} holds no solutions; write a solved set with kinetix levels solve")
    solved = np.flatnonzero(levelset.solutions.solved)
    if not solved.size:
        raise UserError(f"{field}: {path}: no level of the set is solved")
    return solved


def level_at(levelset: LevelSet, index: int) -> Level:
    """Level `index` (0-based) of a loaded set, numpy leaves without the batch axis."""
    count = levelset.manifest["count"]
    if not 0 <= index < count:
        raise UserError(f"--index: {index} is out of range; this set has levels 0..{count - 1}")
    return index_level(levelset.levels, index)
