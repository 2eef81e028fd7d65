"""How fast the studio plays: the round trip of one play step over real HTTP on localhost (the page's request,
the jitted environment step, the scene description, the JSON both ways), per size (`kinetix bench studio`).

The server runs in this process on a free port (uvicorn in a thread); the client holds one keep-alive connection
as a browser does. Each size plays a level from the generator (filled at random to that size's mix) with random
actions, restarting when an episode ends.
"""

from __future__ import annotations

import dataclasses
import http.client
import json
import secrets
import statistics
import tempfile
import time

import numpy as np

from kinetix_cli.studio.app import TOKEN_HEADER
from kinetix_cli.studio.server import serve_in_background
from kinetix_cli.studio.service import Studio


@dataclasses.dataclass(frozen=True)
class StudioBenchConfig:
    sizes: tuple[str, ...] = ("s", "m", "l")
    steps: int = 300
    seed: int = 0


@dataclasses.dataclass(frozen=True)
class StudioBenchResult:
    size: str
    steps: int
    compile_s: float  # the size's play step compiled at start (the studio warms it before printing its URL)
    median_ms: float  # one step's HTTP round trip
    p90_ms: float
    server_ms: float  # median time inside the server (handler only: step, scene, JSON)
    fps: float  # steps per second, one request at a time


def bench_studio(config: StudioBenchConfig, report=lambda r: None) -> list[StudioBenchResult]:
    token = secrets.token_hex(8)
    with tempfile.TemporaryDirectory() as folder:
        studio = Studio(folder)
        server, port = serve_in_background(studio, token)
        try:
            results = []
            rng = np.random.default_rng(config.seed)
            for size in config.sizes:
                start = time.perf_counter()
                studio.warm((size,))
                compile_s = time.perf_counter() - start
                level = studio.generate(size, config.seed)
                # a new connection per size: the server closes one left idle for 5 s (while the next size compiles)
                connection = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
                play = _post(connection, token, "/api/play/start", {"level": level})["play"]
                times, inside = [], []
                for _ in range(config.steps):
                    action = [int(rng.integers(3)) for _ in range(4)] + [int(rng.integers(2)) for _ in range(2)]
                    start = time.perf_counter()
                    frame = _post(connection, token, "/api/play/step", {"play": play, "action": action})
                    times.append(time.perf_counter() - start)
                    inside.append(frame.pop("_server_s"))
                    if frame["ending"]:
                        play = _post(connection, token, "/api/play/start", {"level": level})["play"]
                median = statistics.median(times)
                result = StudioBenchResult(
                    size=size,
                    steps=config.steps,
                    compile_s=compile_s,
                    median_ms=1000 * median,
                    p90_ms=1000 * float(np.percentile(times, 90)),
                    server_ms=1000 * statistics.median(inside),
                    fps=1.0 / median,
                )
                report(result)
                results.append(result)
                connection.close()
            return results
        finally:
            server.should_exit = True


def _post(connection: http.client.HTTPConnection, token: str, path: str, body: dict) -> dict:
    connection.request("POST", path, json.dumps(body), {TOKEN_HEADER: token, "Content-Type": "application/json"})
    response = connection.getresponse()
    data = json.loads(response.read())
    if response.status != 200:
        raise RuntimeError(f"{path}: {response.status} {data}")
    data["_server_s"] = float(response.getheader("Server-Timing", "app;dur=0").split("dur=")[1]) / 1000
    return data
