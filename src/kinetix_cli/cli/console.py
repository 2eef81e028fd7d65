"""What every command shares: the rich consoles (stdout for results, stderr for errors and warnings) and the
parsing of comma-separated options.

Both consoles interpret no markup: file names, level names and error messages are user text and print as they
are (`[draft].json` stays `[draft].json`); colour goes through `say(..., ("ok", "green"))`."""

from __future__ import annotations

from rich.console import Console
from rich.text import Text

from kinetix_cli.errors import UserError

console = Console(soft_wrap=True, markup=False, highlight=False)  # lines stay whole when piped; tables fit
errors = Console(stderr=True, soft_wrap=True, markup=False, highlight=False)


def say(*parts: str | tuple[str, str], stderr: bool = False) -> None:
    """Print one line from plain parts and (text, style) parts; nothing in them is read as markup."""
    (errors if stderr else console).print(Text.assemble(*parts))


def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings print as one line on stderr (a converted level's notes, for example), without a source line."""
    say(("warning:", "yellow"), f" {message}", stderr=True)


MAX_BATCH = 2**24
"""Largest batch a comma-separated --envs list may ask for."""


def int_list(flag: str, text: str, low: int = 1, high: int = MAX_BATCH) -> tuple[int, ...]:
    """'1,64,1024' -> (1, 64, 1024), each in `low..high`; anything else is a `UserError` naming the flag."""
    try:
        values = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise UserError(f"{flag}: expected comma-separated integers, got {text!r}") from None
    if not values or any(v < low for v in values):
        raise UserError(f"{flag}: expected integers >= {low}, got {text!r}")
    if max(values) > high:
        raise UserError(f"{flag}: at most {high:,} each, got {max(values):,}")
    return values


def name_list(text: str) -> tuple[str, ...]:
    """'a, b,c' -> ('a', 'b', 'c')."""
    return tuple(x.strip() for x in text.split(",") if x.strip())
