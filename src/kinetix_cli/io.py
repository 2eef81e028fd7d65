"""Reading and writing the toolkit's files: JSON read with one-line errors, atomic (versioned) writes.

Output discipline, for every file the toolkit writes:
- destinations are checked before the work starts (`check_output_file`, `check_output_dir`): not empty, not a
  folder where a file is expected (or a file where a folder is), never a special file (a FIFO, a device, a socket:
  refused, never replaced), inside a folder that exists or can be made;
- files are written atomically into regular files only (`atomic_write`): a temporary file next to the target,
  fsynced and moved into place; it is removed on every exit path, and the stale temporary files of a killed
  earlier write of the same target are removed first;
- every OS error is one `UserError` line naming the path (a `WriteError` for a failed write, to which a caller that
  keeps partial work adds what was kept).
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, BinaryIO

from kinetix_cli.errors import UserError, WriteError

MAX_JSON_BYTES = 64 * 2**20
"""Largest JSON file the toolkit reads (a level, a manifest, a report) [bytes]."""


def _kind(path: Path) -> str | None:
    """'file', 'folder', 'special file' (FIFO, device, socket), or None when nothing is there."""
    try:
        mode = path.stat().st_mode
    except (FileNotFoundError, NotADirectoryError):  # nothing there (or a file where a parent folder should be)
        return None
    except OSError as exc:
        raise UserError(f"{path}: cannot inspect: {exc.strerror}") from None
    if stat.S_ISREG(mode):
        return "file"
    return "folder" if stat.S_ISDIR(mode) else "special file"


def _creatable(path: Path, flag: str) -> None:
    """Raise (naming `flag`) unless the nearest existing ancestor of `path` is a writable folder."""
    parent = path.parent
    while _kind(parent) is None and parent != parent.parent:
        parent = parent.parent
    if _kind(parent) != "folder":
        raise UserError(f"{flag} {path}: cannot be created: {parent} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise UserError(f"{flag} {path}: cannot be created: {parent} is not writable")


def check_output_file(path: str | os.PathLike | None, flag: str = "output") -> Path:
    """`path` as a destination for a regular file, checked before any work: raises a `UserError` naming `flag` and
    the path for an empty path, a folder, a special file, or a parent that cannot hold it."""
    if path is None or str(path).strip() == "":
        raise UserError(f"{flag}: needs a file name")
    path = Path(path)
    kind = _kind(path)
    if kind == "folder":
        raise UserError(f"{flag} {path}: is a folder; give a file name")
    if kind == "special file":
        raise UserError(f"{flag} {path}: is not a regular file (a FIFO, device or socket); kinetix does not replace it")
    if kind is None:
        _creatable(path, flag)
    elif not os.access(path, os.W_OK) or not os.access(path.parent, os.W_OK | os.X_OK):
        raise UserError(f"{flag} {path}: is not writable")
    return path


def check_output_dir(path: str | os.PathLike | None, flag: str = "output folder") -> Path:
    """`path` as a folder to write into, checked before any work: raises a `UserError` for an empty path, a file
    or special file in its place, or a parent that cannot hold it."""
    if path is None or str(path).strip() == "":
        raise UserError(f"{flag}: needs a folder name")
    path = Path(path)
    kind = _kind(path)
    if kind in ("file", "special file"):
        raise UserError(f"{flag} {path}: is a {kind}, not a folder")
    if kind is None:
        _creatable(path, flag)
    elif not os.access(path, os.W_OK | os.X_OK):
        raise UserError(f"{flag} {path}: is not writable")
    return path


def remove_stale_temporaries(path: Path) -> None:
    """Remove what a killed `atomic_write` of `path` left: `.<name>.*.tmp` next to it."""
    for stale in path.parent.glob(f".{path.name}.*.tmp"):
        stale.unlink(missing_ok=True)


def atomic_write(path: str | os.PathLike, write: Callable[[BinaryIO], None]) -> None:
    """Call `write(file)` on a temporary file next to `path`, then move it into place: readers see the old
    file or the whole new one, never a part. Parent folders are created; the file keeps the permissions it
    had (a new file gets the usual ones, 0o666 less the umask, not mkstemp's private 0o600). A path that is not
    a regular file (a folder, a FIFO, a device) is refused, never replaced; OS errors are one-line `UserError`s."""
    try:
        path = check_output_file(path, "cannot write")
    except UserError as exc:  # the folder turned read-only, or a file took its place, since the work started
        raise WriteError(str(exc)) from None
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temporaries(path)
        mode = path.stat().st_mode & 0o777 if path.exists() else 0o666 & ~current_umask()
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
        os.chmod(tmp, mode)
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
        tmp = None
    except OSError as exc:
        raise WriteError(f"{path}: cannot write: {exc.strerror or exc}") from None
    finally:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)


@contextlib.contextmanager
def atomic_folder(out: Path, flag: str) -> Iterator[Path]:
    """Write a folder whole or not at all: yields an empty folder beside `out` to fill; when the block ends
    well it takes `out`'s place (an existing `out` moves aside first, so a kill leaves one whole folder or the
    other), otherwise it is removed. A failed write is a `UserError` naming `flag` and `out`."""
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent))
    try:
        staging.chmod(0o777 & ~current_umask())  # mkdtemp makes it private; the folder is an ordinary one
        yield staging
        if out.exists():
            old = staging.with_suffix(".old")
            out.rename(old)
            staging.rename(out)
            shutil.rmtree(old)
        else:
            staging.rename(out)
    except OSError as exc:
        raise WriteError(f"{flag} {out}: cannot write: {exc.strerror or exc}") from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)


_STATUS_REASONS = {
    "RESOURCE_EXHAUSTED": "no space left on the device (or a quota reached)",
    "PERMISSION_DENIED": "permission denied",
}
"""What tensorstore's status codes (orbax's writer) mean for a file write."""


def write_reason(exc: BaseException) -> str:
    """Why a write failed, in a few words: the OS error (No space left on device, Read-only file system, Disk
    quota exceeded, ...), a `UserError`'s own line, or the status of a library's writer (orbax reports tensorstore
    statuses such as RESOURCE_EXHAUSTED in a ValueError)."""
    if isinstance(exc, OSError):
        return exc.strerror or str(exc)
    text = str(exc).strip()
    for status, reason in _STATUS_REASONS.items():
        if status in text:
            return reason
    return text.splitlines()[0][:200] if text else type(exc).__name__


def current_umask() -> int:
    """The process's file-creation mask (read without changing it)."""
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
    kind = _kind(path)
    if kind is None:
        raise error(f"{path}: no such file")
    if kind != "file":
        raise error(f"{path}: is a {kind}, not a JSON file")
    try:
        if path.stat().st_size > MAX_JSON_BYTES:
            raise error(f"{path}: {path.stat().st_size:,} bytes; JSON files are read up to {MAX_JSON_BYTES:,}")
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"{path}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise error(f"{path}: cannot read: {exc.strerror}") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise error(f"{path}: not valid JSON: {exc.msg} (line {exc.lineno}, column {exc.colno})") from None
    except RecursionError:
        raise error(f"{path}: not readable JSON: nested too deeply") from None
    except ValueError as exc:  # e.g. an integer literal beyond Python's digit limit
        raise error(f"{path}: not readable JSON: {exc}") from None


def read_format(path: str | os.PathLike, format_name: str, error: type[UserError] = UserError) -> dict:
    """A JSON object written by `atomic_write_json` with `"format": format_name`; any other file or version
    raises `error` naming the file and the format found."""
    payload = read_json(path, error)
    found = payload.get("format") if isinstance(payload, dict) else None
    if found != format_name:
        raise error(f"{path}: format: expected {format_name!r}, got {found!r}")
    return payload
