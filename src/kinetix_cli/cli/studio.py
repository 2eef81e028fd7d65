"""`kinetix studio`: the level studio, a local web app to build, play and watch agents on levels."""

from __future__ import annotations

from pathlib import Path

import typer

from kinetix_cli.cli.console import console, say

commands = typer.Typer()


@commands.command()
def studio(
    path: Path = typer.Argument(
        Path("."), help="Folder of levels to work in (or a level file: its folder, opened on it)."
    ),
    host: str = typer.Option("127.0.0.1", help="Address to listen on (another than localhost exposes the studio)."),
    port: int = typer.Option(8765, min=0, max=65535, help="Port to listen on (0: any free port)."),
    browser: bool = typer.Option(True, "--browser/--no-browser", help="Open the page in the default browser."),
    warm: str = typer.Option("s,m,l", help="Sizes whose play step is compiled before the page opens ('' for none)."),
    allow_host: list[str] = typer.Option(
        [],
        "--allow-host",
        help="A host name requests may give besides localhost and --host (repeatable), for serving it on purpose.",
    ),
) -> None:
    """Build, check, play and watch agents on levels in the browser, on the project's own engine and parser.

    The studio reads and writes only inside PATH. The printed URL carries a per-session token; every request
    needs it, and must be addressed to localhost, --host or an --allow-host name. Ctrl-C stops it."""
    from kinetix_cli.errors import UserError
    from kinetix_cli.studio.server import serve

    folder, level = (path.parent, path.name) if path.is_file() else (path, None)
    if not folder.is_dir():
        raise UserError(f"{path}: no such folder or level file")
    bad = next((h for h in allow_host if not h or any(c in h for c in "/ \t")), None)
    if bad is not None:
        raise UserError(f"--allow-host: expected a host name such as my-machine.local, got {bad!r}")
    sizes = tuple(s for s in warm.split(",") if s)
    if not set(sizes) <= {"s", "m", "l"}:
        raise UserError(f"--warm: expected sizes among s, m, l separated by commas, got {warm!r}")

    def ready(url: str) -> None:
        say(("kinetix studio", "bold"), f" on {folder.resolve()}")
        console.print(f"open {url}\n(Ctrl-C stops it)", soft_wrap=True)

    serve(
        folder,
        host=host,
        port=port,
        open_browser=browser,
        warm=sizes,
        level=level,
        allow_hosts=tuple(allow_host),
        ready=ready,
        progress=lambda text: console.print(text),
    )
    say("studio stopped")
