"""Follow a training run's `config` through the code: which files its pieces visit, in call order, and how often
the path comes back to a file it had already left.

Run from the project's root with the suite's tiny run (tests/helpers/runs.py):

    .venv/bin/python docs/experiments/2026-12-05-readable-training/config_trace.py

Method: `sys.setprofile` sees every Python call while `rl.train.train` runs a tiny 6-update run. A call counts when
one of its arguments is the run's config: the `ExperimentConfig` object itself ("whole"), or it or one of its
sections (`config.env`, `config.ppo`, ...: "any part"). The files of those calls, in order, with repeats in a row
merged, form the path; a "return" is a step of the path into a file that appeared earlier in it. The config's own
package (`kinetix_cli/config/`: loading, saving, the sections' properties) is left out: those calls are the config
answering about itself, not the run passing it on. Prints, for both
kinds, the number of files, the path's length, the returns and the calls, then the files with the most calls of
the whole config.
"""

from __future__ import annotations

import collections
import dataclasses
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
sys.path[:0] = [str(ROOT / "tests"), str(ROOT / "src")]

from helpers.runs import tiny_config  # noqa: E402
from kinetix_cli.config import ExperimentConfig  # noqa: E402
from kinetix_cli.rl.train import train  # noqa: E402


def trace(config: ExperimentConfig) -> tuple[list[str], list[str]]:
    """The source files (relative to src/) of every call that receives `config`, and of every call that receives it
    or one of its sections, in call order."""
    src = str(ROOT / "src") + "/"
    parts = {id(config)} | {id(getattr(config, f.name)) for f in dataclasses.fields(config)}
    whole: list[str] = []
    calls: list[str] = []

    def profile(frame, event, arg):
        if event != "call":
            return
        file = frame.f_code.co_filename
        if not file.startswith(src) or file.startswith(src + "kinetix_cli/config/"):
            return
        code = frame.f_code
        names = code.co_varnames[: code.co_argcount + code.co_kwonlyargcount]
        values = [frame.f_locals.get(name) for name in names]
        if any(value is config for value in values):
            whole.append(file.removeprefix(src))
        if any(id(value) in parts for value in values):
            calls.append(file.removeprefix(src))

    sys.setprofile(profile)
    try:
        with tempfile.TemporaryDirectory() as folder:
            train(config, Path(folder) / "run")
    finally:
        sys.setprofile(None)
    return whole, calls


def summary(calls: list[str]) -> dict:
    path = [file for i, file in enumerate(calls) if i == 0 or file != calls[i - 1]]
    seen: set[str] = set()
    returns = 0
    for file in path:
        returns += file in seen
        seen.add(file)
    return {"files": len(seen), "path": len(path), "returns": returns, "calls": len(calls)}


if __name__ == "__main__":
    whole, calls = trace(tiny_config())
    print("whole:", summary(whole))
    print("any part:", summary(calls))
    for file, count in collections.Counter(whole).most_common(12):
        print(f"{count:5d}  {file}")
