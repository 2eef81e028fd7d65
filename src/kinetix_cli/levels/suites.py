"""The hand-made level suites that ship with the package, addressable by name from any folder.

`levels/s`, `levels/m` and `levels/l` of a checkout install as the data package `kinetix_levels` (the source tree
links `src/kinetix_levels` to `levels/`), so `kinetix eval general-s --levels s` finds them wherever it runs. A path
that exists always wins over a suite of the same name.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

SUITES = ("s", "m", "l")
"""The shipped suites, by the size their levels are made for."""


def suites_root() -> Path:
    """The folder holding the shipped suites (`levels/` of a checkout, or the installed `kinetix_levels`)."""
    spec = importlib.util.find_spec("kinetix_levels")  # a data-only namespace package: its one folder
    return Path(next(iter(spec.submodule_search_locations))).resolve()


def shown_path(path: str | Path) -> str:
    """How results name a level file or folder: a shipped one as `levels/<size>/<file>` wherever it is installed
    (as in a checkout), any other as given."""
    resolved = Path(path).resolve()
    if resolved.is_relative_to(suites_root()):
        return str(Path("levels") / resolved.relative_to(suites_root()))
    return str(path)


def suite_folder(name: str) -> Path:
    """The folder of the shipped suite `name` (one of `SUITES`)."""
    if name not in SUITES:
        raise ValueError(f"unknown suite {name!r}; the shipped suites are {', '.join(SUITES)}")
    return suites_root() / name


def resolve_suite(path: str | Path) -> Path:
    """`path` itself, or the shipped suite it names when no such file or folder exists."""
    path = Path(path)
    if not path.exists() and str(path) in SUITES:
        return suite_folder(str(path))
    return path
