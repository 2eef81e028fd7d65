"""The level suites addressable by name from any folder: the hand-made suites that ship with the package, and the
two suites of the evaluation protocol.

- `s`, `m`, `l`: `levels/s`, `levels/m` and `levels/l` of a checkout, installed as the data package `kinetix_levels`
  (the source tree links `src/kinetix_levels` to `levels/`), so `kinetix eval general-s --levels s` finds them
  wherever it runs.
- `validation`: every choice (recipe, seed, checkpoint, blend, what ships) is made on it: held-out generated levels of
  every size (`levels/validation/{s,m,l}`, generated from seeds no training run draws, `constants.VALIDATION_SEED`;
  `kinetix validation build` rebuilds them) and the hand-made `s`, `m` and `l`.
- `test`: the paper's 74 hand-made levels (`.cache/reference-levels/{s,m,l}` under the current folder, as `make
  reference-levels` writes them), evaluated once per shipped agent after the choice, never read to make it.

A path that exists always wins over a suite of the same name.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

from kinetix_cli.errors import UserError

SUITES = ("s", "m", "l")
"""The shipped hand-made suites, by the size their levels are made for."""
HELDOUT = "validation"
"""The folder under the shipped suites' root holding the held-out generated levels (`validation/<size>/`)."""
REFERENCE_LEVELS = Path(".cache") / "reference-levels"
"""Where `make reference-levels` unzips the paper's 74 levels (relative to the checkout)."""
NAMED = ("validation", "test")
"""The protocol's suites: each names several folders."""


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


def heldout_folder(size: str) -> Path:
    """The folder of the validation suite's held-out generated levels of `size`."""
    return suites_root() / HELDOUT / size


def named_suite(name: str) -> list[Path]:
    """The folders of the protocol's suite `name` (one of `NAMED`); a `UserError` saying how to get them when they
    are missing."""
    if name == "validation":
        folders = [heldout_folder(size) for size in SUITES] + [suite_folder(size) for size in SUITES]
        how = "kinetix validation build writes the held-out levels"
    elif name == "test":
        folders = [REFERENCE_LEVELS / size for size in SUITES]
        how = "make reference-levels unzips the paper's 74 levels (run it in the checkout)"
    else:
        raise ValueError(f"unknown suite {name!r}; the protocol's suites are {', '.join(NAMED)}")
    missing = [str(folder) for folder in folders if not any(folder.glob("*.json"))]
    if missing:
        raise UserError(f"--levels {name}: {', '.join(missing)}: no level files; {how}")
    return folders


def resolve_suite(path: str | Path) -> list[Path]:
    """`path` itself, or the folders of the suite it names when no such file or folder exists."""
    path = Path(path)
    if path.exists():
        return [path]
    if str(path) in SUITES:
        return [suite_folder(str(path))]
    if str(path) in NAMED:
        return named_suite(str(path))
    return [path]
