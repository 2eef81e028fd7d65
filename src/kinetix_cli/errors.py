"""User-facing errors: one clear line naming the file and field, and exit code 2."""

from __future__ import annotations


class UserError(Exception):
    """Bad input from the user (a file, a flag, a config key). The CLI prints it and exits with code 2."""

    exit_code = 2


class LevelError(UserError):
    """A level file that cannot be loaded: the message names the file, the entity and the field."""


class WriteError(UserError):
    """A file or folder that could not be written (a full disk, a quota, a read-only folder): the message names the
    path and the reason; callers that keep partial work add what was kept."""


class Stopped(Exception):
    """A training run stopped by a signal (SIGTERM, Ctrl-C) after a complete update, which it checkpointed: `--resume`
    continues it. The CLI prints it as one line and exits with 128 + the signal's number, as a shell reports a
    process that signal ended."""

    def __init__(self, message: str, signum: int):
        super().__init__(message)
        self.exit_code = 128 + signum
