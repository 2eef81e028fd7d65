"""The folder a studio works in: every path a request names is resolved inside it, and levels are read and written
there only.

A path is relative, POSIX-style, without `..`, and after symlinks are followed it still lies inside the folder;
anything else is refused (403) before any file is touched. Hidden files (a part starting with `.`) are neither
listed, read nor written. Writes are atomic (`io.atomic_write_text`), go only into folders that exist, under plain
names (no `%`, control character or leading `-`), hold a JSON object of finite numbers, never replace another file
without `overwrite`, and never replace a valid level with an invalid one.
"""

from __future__ import annotations

import json
import math
from pathlib import Path, PurePosixPath
from typing import Any

from kinetix_cli.constants import LEVEL_FORMAT
from kinetix_cli.errors import UserError
from kinetix_cli.io import MAX_JSON_BYTES
from kinetix_cli.levels.files import save_level
from kinetix_cli.levels.format import brief
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.reference import convert_reference_level, is_reference_level

MAX_FILES = 2000
"""Level files listed per folder (the first ones by path)."""
MAX_LEVEL_BYTES = 256 * 2**10
"""Largest level the studio saves [bytes of JSON]: a level of size l is ~20 KB."""


class StudioError(Exception):
    """A request the studio refuses: an HTTP status and one line for the page."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status
        self.message = message


class Workspace:
    """The level files under one folder."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root).resolve()

    def path(self, name: Any) -> Path:
        """The file `name` (relative to the folder) names; a path that could leave the folder is a 403."""
        if not isinstance(name, str) or not name or len(name) > 512 or "\\" in name or "\x00" in name:
            raise StudioError(400, f"path: expected a relative file path, got {json.dumps(name)[:80]}")
        pure = PurePosixPath(name)
        if pure.is_absolute() or ".." in pure.parts or name.startswith("~"):
            raise StudioError(403, f"{name}: outside the studio's folder (use a path relative to it, without ..)")
        if any(part.startswith(".") for part in pure.parts):
            raise StudioError(403, f"{name}: a hidden file or folder (a name starting with '.'); the studio shows none")
        path = (self.root / pure).resolve()
        if not path.is_relative_to(self.root):
            raise StudioError(403, f"{name}: leads outside the studio's folder (a symbolic link?)")
        return path

    def name(self, path: Path) -> str:
        return path.relative_to(self.root).as_posix()

    def files(self) -> list[dict]:
        """Every `.json` file under the folder (hidden folders skipped), with its level name and whether it is a
        valid level (reference-format files count as levels when they convert)."""
        found = []
        for path in sorted(self.root.rglob("*.json")):
            rel = path.relative_to(self.root)
            if any(part.startswith(".") for part in rel.parts) or not path.resolve().is_relative_to(self.root):
                continue
            if len(found) == MAX_FILES:
                break
            entry = {"path": rel.as_posix(), "name": path.stem, "valid": False, "error": None}
            try:
                data, _ = self.read(rel.as_posix())
                entry["name"] = parse_level(data, rel.as_posix()).name
                entry["valid"] = True
            except (StudioError, UserError) as exc:
                entry["error"] = getattr(exc, "message", str(exc))
            found.append(entry)
        return found

    def read(self, name: str) -> tuple[Any, list[str]]:
        """(JSON value, import notes) of a level file; a reference-format file is converted (its notes say what
        did not carry over). Unreadable, non-UTF-8 or malformed files are 4xx errors naming the file."""
        path = self.path(name)
        if not path.is_file():
            raise StudioError(404, f"{name}: no such file")
        if path.stat().st_size > MAX_JSON_BYTES:
            raise StudioError(
                413, f"{name}: {path.stat().st_size:,} bytes; level files are read up to {MAX_JSON_BYTES:,}"
            )
        try:
            data = json.loads(path.read_bytes().decode("utf-8"))
        except UnicodeDecodeError as exc:
            raise StudioError(422, f"{name}: not UTF-8 text (byte {exc.start})") from None
        except (json.JSONDecodeError, RecursionError) as exc:
            where = f" (line {exc.lineno}, column {exc.colno})" if isinstance(exc, json.JSONDecodeError) else ""
            raise StudioError(422, f"{name}: not valid JSON{where}") from None
        where = non_finite(data)
        if where is not None:
            raise StudioError(422, f"{name}: {where}: not a finite number (NaN or Infinity); fix it in a text editor")
        if is_reference_level(data):
            try:
                data, notes = convert_reference_level(data, name)
            except UserError as exc:
                raise StudioError(422, str(exc)) from None
            return data, [str(n) for n in notes]
        return data, []

    def save(self, name: str, level: Any, *, overwrite: bool, valid: bool) -> str:
        """Write `level` (a JSON object) to `name` atomically, in the layout people read, into a folder that
        exists. An existing file is replaced only with `overwrite`; an invalid level (a draft) never replaces a
        valid one."""
        path = self.writable(name)
        if not isinstance(level, dict):
            raise StudioError(400, f"level: expected a JSON object, got {type(level).__name__}")
        if level.get("format") != LEVEL_FORMAT:
            raise StudioError(
                400, f"level: format: expected {json.dumps(LEVEL_FORMAT)}, got {brief(level.get('format'))}"
            )
        where = non_finite(level)
        if where is not None:
            raise StudioError(400, f"level: {where}: not a finite number")
        size = len(json.dumps(level))
        if size > MAX_LEVEL_BYTES:
            raise StudioError(413, f"level: {size:,} bytes of JSON; the studio saves at most {MAX_LEVEL_BYTES:,}")
        if path.exists():
            if not path.is_file():
                raise StudioError(409, f"{name}: is a folder, not a level file")
            if not overwrite:
                raise StudioError(409, f"{name}: exists; confirm to overwrite it")
            if not valid and self._is_valid(name):
                raise StudioError(409, f"{name}: holds a valid level; an invalid draft cannot replace it")
        try:
            save_level(path, level)
        except UserError as exc:
            raise StudioError(500, str(exc)) from None
        return self.name(path)

    def writable(self, name: Any) -> Path:
        """The file `name` names, if the studio may write it: inside the folder, in a folder that exists (the
        studio creates none), a `.json` name of plain characters."""
        path = self.path(name)
        bad = next((c for c in name if c == "%" or not c.isprintable()), None)
        if bad is not None:
            raise StudioError(400, f"{name}: {bad!r} in a file name; use plain characters")
        if any(part.startswith("-") for part in PurePosixPath(name).parts):
            raise StudioError(400, f"{name}: a name starting with '-' reads as an option on a command line")
        if path.suffix != ".json":
            raise StudioError(400, f"{name}: level files end in .json")
        if not path.parent.is_dir():
            folder = self.name(path.parent)
            raise StudioError(404, f"{folder}/: no such folder; the studio writes into folders that exist")
        return path

    def _is_valid(self, name: str) -> bool:
        try:
            parse_level(self.read(name)[0], name)
        except (StudioError, UserError):
            return False
        return True


def non_finite(value: Any) -> str | None:
    """Where in a JSON value the first non-finite float (NaN, Infinity) lies, e.g. `bodies[0].position[1]`
    (`"(top level)"` for the value itself), or None when every number is finite. Iterative: a deeply nested
    value is no recursion."""
    stack = [("", value)]
    while stack:
        where, item = stack.pop()
        if isinstance(item, float) and not math.isfinite(item):
            return where or "(top level)"
        if isinstance(item, dict):
            stack += reversed([(f"{where}.{k}" if where else str(k), v) for k, v in item.items()])
        elif isinstance(item, list):
            stack += reversed([(f"{where}[{i}]", v) for i, v in enumerate(item)])
    return None
