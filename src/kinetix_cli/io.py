"""Reading and writing the toolkit's files: JSON read with one-line errors, atomic (versioned) writes."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, BinaryIO

from kinetix_cli.errors import UserError


def atomic_write(path: str | os.PathLike, write: Callable[[BinaryIO], None]) -> None:
    """Call `write(file)` on a temporary file next to `path`, then move it into place: readers see the old
    file or the whole new one, never a part. Parent folders are created; the file keeps the permissions it
    had (a new file gets the usual ones, 0o666 less the umask, not mkstemp's private 0o600)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    mode = path.stat().st_mode & 0o777 if path.exists() else 0o666 & ~_umask()
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.chmod(tmp, mode)
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_text(path: str | os.PathLike, text: str) -> None:
    """Write `text` (UTF-8) to `path` atomically."""
    atomic_write(path, lambda f: f.write(text.encode()))


def atomic_write_json(path: str | os.PathLike, payload: dict, format_name: str) -> None:
    """Write `payload` as JSON with a leading `"format": format_name` version tag."""
    atomic_write_text(path, json.dumps({"format": format_name, **payload}, indent=2) + "\n")


def read_json(path: str | os.PathLike, error: type[UserError] = UserError) -> Any:
    """The JSON value of a file; a missing, unreadable or malformed file raises `error` naming the file."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except UnicodeDecodeError as exc:
        raise error(f"{path}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise error(f"{path}: cannot read: {exc.strerror}") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise error(f"{path}: not valid JSON: {exc.msg} (line {exc.lineno}, column {exc.colno})") from None


def read_format(path: str | os.PathLike, format_name: str, error: type[UserError] = UserError) -> dict:
    """A JSON object written by `atomic_write_json` with `"format": format_name`; any other file or version
    raises `error` naming the file and the format found."""
    payload = read_json(path, error)
    found = payload.get("format") if isinstance(payload, dict) else None
    if found != format_name:
        raise error(f"{path}: format: expected {format_name!r}, got {found!r}")
    return payload
