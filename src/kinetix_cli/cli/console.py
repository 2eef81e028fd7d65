"""What every command shares: the rich consoles (stdout for results, stderr for errors and warnings) and the
parsing of comma-separated options."""

from __future__ import annotations

from rich.console import Console

from kinetix_cli.errors import UserError

console = Console(soft_wrap=True)  # text lines stay whole when piped; tables still fit the width
errors = Console(stderr=True, soft_wrap=True)


def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings print as one line on stderr (a converted level's notes, for example), without a source line."""
    errors.print(f"[yellow]warning:[/yellow] {message}", highlight=False)


def int_list(flag: str, text: str) -> tuple[int, ...]:
    """'1,64,1024' -> (1, 64, 1024); anything else is a `UserError` naming the flag."""
    try:
        values = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise UserError(f"{flag}: expected comma-separated integers, got {text!r}") from None
    if not values or any(v < 1 for v in values):
        raise UserError(f"{flag}: expected positive integers, got {text!r}")
    return values


def name_list(text: str) -> tuple[str, ...]:
    """'a, b,c' -> ('a', 'b', 'c')."""
    return tuple(x.strip() for x in text.split(",") if x.strip())
