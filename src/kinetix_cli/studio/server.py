"""Run the studio: warm the compiled play steps, bind the address, print the URL with the session's token, open
the browser, serve until Ctrl-C."""

from __future__ import annotations

import secrets
import signal
import socket
import threading
import urllib.parse
import webbrowser
from collections.abc import Callable
from pathlib import Path

import uvicorn

from kinetix_cli.errors import UserError
from kinetix_cli.studio.app import create_app, release_memory
from kinetix_cli.studio.service import Studio


def serve(
    folder: Path,
    *,
    host: str = "127.0.0.1",
    port: int = 8765,
    open_browser: bool = True,
    warm: tuple[str, ...] = ("s", "m", "l"),
    level: str | None = None,
    allow_hosts: tuple[str, ...] = (),
    ready: Callable[[str], None] = print,
    progress: Callable[[str], None] = print,
) -> None:
    """Serve the studio on `folder` until interrupted; `ready(url)` is called once it accepts requests. Requests
    must name localhost, `host` or one of `allow_hosts` in their `Host` header."""
    studio = Studio(folder)
    token = secrets.token_urlsafe(24)
    try:
        sock = socket.create_server((host, port))
    except OSError as exc:
        raise UserError(
            f"--host {host} --port {port}: cannot listen there ({exc.strerror or exc}); try --port 0"
        ) from None
    for size in warm:
        progress(f"compiling the play step of size {size}...")
        studio.warm((size,))
        release_memory()
    bound = sock.getsockname()[1]
    shown = "127.0.0.1" if host in ("0.0.0.0", "") else host
    query = {"token": token} | ({"level": level} if level else {})
    url = f"http://{shown}:{bound}/?{urllib.parse.urlencode(query)}"
    app = create_app(studio, token, port=bound, hosts=(host, *allow_hosts))
    config = uvicorn.Config(app, log_level="warning", lifespan="off")
    server = uvicorn.Server(config)

    def announce() -> None:
        while not server.started:
            if server.should_exit:
                return
            threading.Event().wait(0.05)
        ready(url)
        if open_browser:
            webbrowser.open(url)

    threading.Thread(target=announce, daemon=True).start()
    # uvicorn shuts down on SIGINT or SIGTERM, then raises the signal again with the handlers it found: both end
    # here as KeyboardInterrupt, so Ctrl-C and `kill` stop the studio with its closing line and exit code 0.
    before = signal.signal(signal.SIGTERM, _interrupt)
    try:
        server.run(sockets=[sock])
    except KeyboardInterrupt:
        pass
    finally:
        signal.signal(signal.SIGTERM, before)
        sock.close()


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


def serve_in_background(studio: Studio, token: str) -> tuple[uvicorn.Server, int]:
    """`studio` served on a free localhost port from a daemon thread, for benchmarks, tests and screenshots:
    (server, port), once it accepts requests; `server.should_exit = True` stops it."""
    sock = socket.create_server(("127.0.0.1", 0))
    app = create_app(studio, token, port=sock.getsockname()[1])
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", lifespan="off"))
    threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True).start()
    while not server.started:
        threading.Event().wait(0.02)
    return server, sock.getsockname()[1]
