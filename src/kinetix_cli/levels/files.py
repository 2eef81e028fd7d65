"""Level files on disk: find them, load them (`kinetix-level/1`, or the reference Kinetix format converted on the
way), import reference files, and write level files.

A reference-format file loads everywhere a level file does; what its conversion cannot carry over is reported as
a `ConversionWarning` per note (the CLI prints each as a one-line warning).
"""

from __future__ import annotations

import warnings
from pathlib import Path

from kinetix_cli.errors import LevelError, UserError
from kinetix_cli.io import atomic_write_text, read_json
from kinetix_cli.levels.format import format_level_json
from kinetix_cli.levels.levelset import MANIFEST_FILE, PROGRESS_FILE
from kinetix_cli.levels.parse import LevelSpec, parse_level
from kinetix_cli.levels.reference import Note, convert_reference_level, is_reference_level
from kinetix_cli.levels.suites import resolve_suite


class ConversionWarning(UserWarning):
    """A reference-format level was loaded, but something in it could not be carried over (file: entity: field)."""


def level_paths(paths: list[str | Path] | tuple[str | Path, ...]) -> list[Path]:
    """Level files named by `paths`, with folders expanded into their *.json files (sorted, recursively); a name
    of a shipped suite ('s', 'm', 'l') or of the protocol ('validation', 'test') that is not a path here means that
    suite (`levels.suites`). A missing path or a folder without level files is a `UserError`."""
    files: list[Path] = []
    for path in (folder for named in paths for folder in resolve_suite(named)):
        if path.is_dir():
            found = sorted(path.rglob("*.json"))
            for folder in sorted({f.parent for f in found}):
                if (folder / MANIFEST_FILE).is_file() or (folder / PROGRESS_FILE).is_file():
                    raise UserError(
                        f"{folder}: a generated level set, not level files; train on it with `kinetix pretrain "
                        "--levels`, or write levels out with `kinetix levels export`"
                    )
            if not found:
                raise UserError(f"{path}: no level files (*.json) in this folder")
            files += found
        elif path.exists():
            files.append(path)
        else:
            raise UserError(f"{path}: no such file or folder (the named suites are s, m, l, validation and test)")
    return files


def load_level(path: str | Path) -> LevelSpec:
    """Read and validate a level file. Raises `LevelError` with the file, entity and field.

    A file in the reference Kinetix format is converted on the way (`kinetix_cli.levels.reference`); what the
    conversion cannot carry over is reported as a `ConversionWarning` per note.
    """
    path = Path(path)
    data = read_json(path, LevelError)
    if is_reference_level(data):
        data, notes = convert_reference_level(data, str(path))
        for note in notes:
            warnings.warn(f"{path}: {note}", ConversionWarning, stacklevel=2)
    return parse_level(data, str(path))


def save_level(path: str | Path, data: dict) -> None:
    """Write a level's JSON value (`kinetix-level/1`) to `path` atomically, in the layout people read."""
    atomic_write_text(path, format_level_json(data))


def import_targets(paths: list[Path], out: Path) -> list[tuple[Path, Path]]:
    """(source, target) pairs of `kinetix import PATHS -o OUT`: a file lands in OUT under its name, a folder's files
    under their path inside the folder. Two sources landing on one target (the paper's m/ and l/ folders both hold
    h1_car_left.json) are a `UserError` before anything is written: nothing is overwritten silently."""
    pairs, seen = [], {}
    for path in map(Path, paths):
        for source in level_paths([path]):
            target = out / (source.relative_to(path) if path.is_dir() else source.name)
            if target in seen:
                raise UserError(
                    f"{seen[target]} and {source} would both be written to {target}; import them into separate "
                    "folders, or import their common parent folder"
                )
            seen[target] = source
            pairs.append((source, target))
    return pairs


def import_reference_file(source: Path, out: Path) -> list[Note]:
    """Convert the reference-format level file `source` and write it to `out` (atomically); return the notes.

    Raises:
        LevelError: `source` cannot be read, is not JSON, is already a `kinetix-level` file, or is malformed.
    """
    data = read_json(source, LevelError)
    if not is_reference_level(data):
        raise LevelError(f"{source}: not a reference-format level (no env_state); kinetix-level files need no import")
    converted, notes = convert_reference_level(data, str(source))
    parse_level(converted, str(source)).build()  # the written file must load
    save_level(out, converted)
    return notes
