"""The studio's HTTP server: a Starlette app over `Studio`, serving the page and a JSON API.

Every request must name this machine in its `Host` header (localhost, the bound address, or a host the user
allowed), which refuses DNS-rebinding pages, and carry the session's token: the page and its files by the `token`
query parameter of the printed URL (then by a cookie the page sets, named after the port: HttpOnly,
SameSite=Strict), the API by the `X-Studio-Token` header, which another web page cannot add to a request to this
origin. Request bodies are JSON objects of at most `MAX_BODY` bytes holding finite numbers only. A refused or
malformed request gets a 4xx JSON `{"error": "..."}` naming what was wrong; the server keeps running and nothing is
written. Every answer is JSON a browser parses: a non-finite float never goes on the wire.

    GET  /                     the page            GET  /api/files              level files in the folder
    GET  /api/level?path=P     a level's JSON      GET  /api/thumbnail?path=P   a level's PNG thumbnail
    GET  /api/agents           shipped agents      POST /api/check {level}      validate, and the scene to draw
    POST /api/save {path, level, overwrite}        POST /api/generate {size, seed}
    POST /api/mutate {level, seed, edits}          POST /api/play/start {level}
    POST /api/play/step {play, action, steps}      POST /api/play/solution {play, level}
    POST /api/watch/start {level, agent, seed}     POST /api/evaluate {level, agent, attempts, path}
    (an agent's episode steps through /api/play/step without an action: its agent chooses)
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import html
import io
import json
import math
import secrets
import sys
import time
import traceback
from collections.abc import Iterable
from importlib import resources
from typing import Any

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.requests import ClientDisconnect, Request
from starlette.responses import HTMLResponse, JSONResponse, Response
from starlette.routing import Route
from starlette.types import ASGIApp, Receive, Scope, Send

from kinetix_cli.errors import UserError
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.studio.service import Studio
from kinetix_cli.studio.workspace import StudioError, non_finite
from kinetix_cli.viz.render import render_level

MAX_BODY = 2 * 2**20
"""Largest request body [bytes]: a level of size l is ~20 KB of JSON."""
TOKEN_HEADER = "X-Studio-Token"
SLOW_REQUEST = 1.0
"""A request that took longer [s] compiled something: the memory XLA's compiler freed is handed back after it."""
LOCAL_HOSTS = ("localhost", "127.0.0.1", "::1")
"""Names of this machine every studio accepts in a request's `Host` header (besides its bound address)."""
MODULES = ("studio", "core", "draw", "level", "editing", "forms", "mouse", "play", "files")
"""The page's ES modules (`static/<name>.js`, served as they are: no build step); `studio.js` imports the rest."""
STATIC = {f"{name}.js": "text/javascript" for name in MODULES} | {"studio.css": "text/css"}
"""The page's files (package data in kinetix_cli/studio/static/) and their media types."""
SECURITY_HEADERS = {
    "Content-Security-Policy": "default-src 'self'; img-src 'self' data: blob:; frame-ancestors 'none'",
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-store",
}


def cookie_name(port: int) -> str:
    """The session cookie's name: one per port, so that two studios on one machine keep their own."""
    return f"kinetix_studio_{port}"


def create_app(studio: Studio, token: str, *, port: int, hosts: Iterable[str] = ()) -> ASGIApp:
    """The studio app; `token` is the session's secret (the printed URL carries it), `port` the port it is served
    on (it names the cookie), `hosts` the names besides `LOCAL_HOSTS` a request's `Host` header may give (the bound
    address, and those the user allowed with `--allow-host`)."""
    cookie = cookie_name(port)

    def authorised(request: Request, *, api: bool) -> bool:
        given = request.headers.get(TOKEN_HEADER, "") if api else request.query_params.get("token", "")
        given = given or ("" if api else request.cookies.get(cookie, ""))
        return secrets.compare_digest(given.encode(), token.encode())

    def guarded(handler, *, api: bool = True, body: bool = False, locked: bool = True):
        """`handler(studio, args)` as an endpoint: token checked, arguments read (a JSON body or the query), run
        on a worker thread (under the studio's lock unless `locked` is False: a pure handler touching no state
        of the studio, such as a generator's first compile, does not hold up the others)."""

        @functools.wraps(handler)
        async def endpoint(request: Request) -> Response:
            if not authorised(request, api=api):
                what = f"the {TOKEN_HEADER} header" if api else "the token in the URL the studio printed"
                return _error(403, f"missing or wrong token: open the studio with {what}")
            try:
                args = await _json_body(request) if body else dict(request.query_params)
                start = time.perf_counter()
                result = await run_in_threadpool(_locked if locked else _call, studio, handler, args)
                elapsed = time.perf_counter() - start
                if elapsed > SLOW_REQUEST:
                    release_memory()
                timing = {"Server-Timing": f"app;dur={1000 * elapsed:.3f}"}
                if isinstance(result, Response):
                    return result
                return _Json(result, headers=SECURITY_HEADERS | timing)
            except StudioError as exc:
                return _error(exc.status, exc.message)
            except ClientDisconnect:  # the page went away mid-request: nobody to answer
                return Response(status_code=400)
            except Exception as exc:  # a bug: say so on the page, keep serving, print the trace for a report
                traceback.print_exc(file=sys.stderr)
                return _error(500, f"internal error ({type(exc).__name__}): {exc}"[:300])

        return endpoint

    async def page(request: Request) -> Response:
        if not authorised(request, api=False):
            return HTMLResponse(
                "<p>kinetix studio: open the URL the studio printed (it carries the session's token).</p>",
                status_code=403,
                headers=SECURITY_HEADERS,
            )
        text = resources.files("kinetix_cli.studio").joinpath("static/index.html").read_text(encoding="utf-8")
        response = HTMLResponse(text.replace("{{TOKEN}}", html.escape(token)), headers=SECURITY_HEADERS)
        response.set_cookie(cookie, token, httponly=True, samesite="strict")
        return response

    async def static(request: Request) -> Response:
        name = request.path_params["name"]
        if not authorised(request, api=False):
            return _error(403, "missing or wrong token")
        if name not in STATIC:
            return _error(404, f"{name}: no such file")
        data = resources.files("kinetix_cli.studio").joinpath(f"static/{name}").read_bytes()
        return Response(data, media_type=STATIC[name], headers=SECURITY_HEADERS)

    def post(path: str, handler, *, locked: bool = True):
        return Route(path, guarded(handler, body=True, locked=locked), methods=["POST"])

    def get(path: str, handler):
        return Route(path, guarded(handler), methods=["GET"])

    routes = [
        Route("/", page, methods=["GET"]),
        Route("/static/{name}", static, methods=["GET"]),
        get("/api/files", lambda s, a: {"root": str(s.workspace.root), "files": s.workspace.files()}),
        get("/api/level", _read_level),
        get("/api/thumbnail", _thumbnail),
        get("/api/agents", lambda s, a: {"agents": s.agents()}),
        post("/api/check", lambda s, a: s.check(_field(a, "level")), locked=False),
        post("/api/save", _save),
        post("/api/generate", lambda s, a: {"level": s.generate(_field(a, "size"), a.get("seed", 0))}, locked=False),
        post(
            "/api/mutate",
            lambda s, a: {"level": s.mutate(_field(a, "level"), a.get("seed", 0), a.get("edits", 1))},
            locked=False,
        ),
        post("/api/play/start", lambda s, a: s.play_start(_field(a, "level"))),
        post("/api/play/step", lambda s, a: s.play_step(_field(a, "play"), a.get("action"), a.get("steps", 1))),
        post("/api/play/solution", lambda s, a: {"level": s.play_solution(_field(a, "play"), _field(a, "level"))}),
        post("/api/watch/start", lambda s, a: s.watch_start(_field(a, "level"), _field(a, "agent"), a.get("seed", 0))),
        post(
            "/api/evaluate",
            lambda s, a: s.evaluate(_field(a, "level"), _field(a, "agent"), a.get("attempts", 50), a.get("path")),
        ),
    ]
    return _HostCheck(Starlette(routes=routes), {*LOCAL_HOSTS, *(h.lower().strip("[]") for h in hosts)})


class _HostCheck:
    """ASGI middleware: a request whose `Host` header names another machine is refused (403) before any route
    sees it, as Jupyter does: a page on another site that rebinds its name to 127.0.0.1 sends its own name."""

    def __init__(self, app: ASGIApp, allowed: set[str]) -> None:
        self.app = app
        self.allowed = allowed

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            host = dict(scope["headers"]).get(b"host", b"").decode("latin-1")
            if host_name(host) not in self.allowed:
                shown = json.dumps(host)[:80]
                message = f"Host {shown}: the studio answers requests to localhost only (see --allow-host)"
                await _error(403, message)(scope, receive, send)
                return
        await self.app(scope, receive, send)


def host_name(host: str) -> str:
    """The name in a `Host` header, lower case, without the port or an IPv6 address's brackets."""
    host = host.strip().lower()
    if host.startswith("["):
        return host[1:].partition("]")[0]
    return host.rpartition(":")[0] if host.count(":") == 1 else host


def release_memory() -> None:
    """Hand the heap's free pages back to the system (glibc's `malloc_trim`; elsewhere nothing). XLA's compiler
    frees hundreds of MB per program, which glibc keeps: the studio held 1.2 GB after compiling its three play steps,
    0.65 GB with this after each."""
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL("libc.so.6").malloc_trim(0)


def _call(studio: Studio, handler, args: dict) -> Any:
    return handler(studio, args)


def _locked(studio: Studio, handler, args: dict) -> Any:
    with studio.lock:
        return handler(studio, args)


class _Json(JSONResponse):
    """A JSON answer in which a non-finite float (a physics state that blew up) is `null`: JavaScript's
    `JSON.parse` reads no `NaN` or `Infinity`."""

    def render(self, content: Any) -> bytes:
        return json.dumps(_finite(content), ensure_ascii=False, allow_nan=False, separators=(",", ":")).encode()


def _finite(value: Any) -> Any:
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    return value


def _error(status: int, message: str) -> JSONResponse:
    return _Json({"error": message}, status_code=status, headers=SECURITY_HEADERS)


async def _json_body(request: Request) -> dict:
    """The request's JSON object; too large, not UTF-8, not JSON or not an object is a 4xx `StudioError`."""
    declared = request.headers.get("content-length")
    if declared is not None and (not declared.isdigit() or int(declared) > MAX_BODY):
        raise StudioError(413, f"request body: at most {MAX_BODY:,} bytes")
    data = bytearray()
    async for chunk in request.stream():
        data += chunk
        if len(data) > MAX_BODY:
            raise StudioError(413, f"request body: at most {MAX_BODY:,} bytes")
    try:
        value = json.loads(data.decode("utf-8"))
    except UnicodeDecodeError:
        raise StudioError(400, "request body: not UTF-8 text") from None
    except (json.JSONDecodeError, RecursionError):
        raise StudioError(400, "request body: not valid JSON") from None
    if not isinstance(value, dict):
        raise StudioError(400, f"request body: expected a JSON object, got {type(value).__name__}")
    where = non_finite(value)
    if where is not None:
        raise StudioError(400, f"request body: {where}: not a finite number (JSON holds no NaN or Infinity)")
    return value


def _field(args: dict, name: str) -> Any:
    if name not in args:
        raise StudioError(400, f"{name}: missing from the request")
    return args[name]


def _read_level(studio: Studio, args: dict) -> dict:
    path = _field(args, "path")
    data, notes = studio.workspace.read(path)
    return {"path": path, "level": data, "notes": notes, "check": studio.check(data)}


def _thumbnail(studio: Studio, args: dict) -> Response:
    path = _field(args, "path")
    data, _ = studio.workspace.read(path)
    try:
        spec = parse_level(data, path)
        image = render_level(spec.build(), scale=24)
    except UserError as exc:
        raise StudioError(422, str(exc)) from None
    buffer = io.BytesIO()
    image.save(buffer, format="PNG")
    return Response(buffer.getvalue(), media_type="image/png", headers=SECURITY_HEADERS)


def _save(studio: Studio, args: dict) -> dict:
    level, overwrite = _field(args, "level"), args.get("overwrite", False)
    if not isinstance(overwrite, bool):
        raise StudioError(400, f"overwrite: expected true or false, got {overwrite!r}")
    studio.workspace.writable(_field(args, "path"))
    check = studio.check(level)
    saved = studio.workspace.save(_field(args, "path"), level, overwrite=overwrite, valid=check["ok"])
    return {"path": saved, "valid": check["ok"], "error": check.get("error")}
