"""Running `kinetix` as a user does (through `main`, so errors become lines and exit codes) inside a test."""

from __future__ import annotations

import dataclasses
import sys

import pytest

from kinetix_cli.cli.app import main


@dataclasses.dataclass
class Result:
    code: int
    out: str
    err: str

    @property
    def error_line(self) -> str:
        """The one error line, asserting that the command failed with exit code 2 and printed exactly that."""
        lines = self.err.strip().splitlines()
        assert self.code == 2, f"exit code {self.code}, stderr {self.err!r}, stdout {self.out[-500:]!r}"
        assert "Traceback" not in self.err and len(lines) == 1, self.err
        assert lines[0].startswith("error: "), lines[0]
        return lines[0]


def kinetix(capsys, *args: str) -> Result:
    """Run `kinetix ARGS` in this process; returns the exit code and what it printed."""
    capsys.readouterr()
    argv = sys.argv
    sys.argv = ["kinetix", *map(str, args)]
    try:
        with pytest.raises(SystemExit) as info:
            main()
    finally:
        sys.argv = argv
    captured = capsys.readouterr()
    return Result(info.value.code if isinstance(info.value.code, int) else 1, captured.out, captured.err)
