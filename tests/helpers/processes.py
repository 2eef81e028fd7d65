"""`kinetix` as separate processes: with forced host devices (`FORCE_2`), or as the processes of one
multi-process run on localhost (a free port, every process bounded by a timeout and killed on failure)."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time

KINETIX = [sys.executable, "-c", "from kinetix_cli.cli.app import main; main()"]
FORCE_2 = "--xla_force_host_platform_device_count=2"
"""XLA_FLAGS giving a process 2 CPU devices."""
TIMEOUT = 600
"""A bound on every process [s]: a hang fails the test instead of stalling the suite."""


FAST_CODEGEN = "--xla_cpu_use_fusion_emitters=false"
"""XLA flag of the suite (tests/conftest.py sets it for the suite and every process it starts): XLA's CPU backend
emits fused loops with its older elemental emitter instead of the MLIR fusion emitters, which compiles the suite's
programs ~40% faster (the tiny SFL run's first update: 27 s -> 16 s with FAST_COMPILE; the suite's CPU time 18.7
-> 9.6 min) and runs them no slower. Seen: with it, a level set generated on 2 devices is not byte for byte the one
generated on 1 (without it, it is), so the checks of that promise run without it (`exact_env`)."""


def process_env() -> dict:
    """The environment of a started process: this one's, with the suite's compile cache (tests/conftest.py), so
    processes that compile the same programs compile them once."""
    return dict(os.environ)


FAST_COMPILE = "JAX_DISABLE_MOST_OPTIMIZATIONS"
"""Environment variable of the suite (tests/conftest.py sets it for the suite and every process it starts): XLA
skips most optimisation passes, so the suite's tiny programs compile faster."""


def release_env() -> dict:
    """`exact_env` without `FAST_COMPILE` either: compiled exactly as `kinetix` compiles outside the suite. The suite's
    settings round float32 differently in places (fusion and pass order), which can flip a marginal contact-rich
    episode: a recorded level solution is checked here, where users replay it."""
    env = exact_env()
    env.pop(FAST_COMPILE, None)
    return env


def exact_env() -> dict:
    """`process_env` without `FAST_CODEGEN`: XLA's default code generation, that of `kinetix` outside the suite."""
    env = process_env()
    env["XLA_FLAGS"] = " ".join(flag for flag in env.get("XLA_FLAGS", "").split() if flag != FAST_CODEGEN)
    return env


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def start(args: list, env: dict, **extra) -> subprocess.Popen:
    """`kinetix ARGS` started with `env` plus the variables `extra` (XLA_FLAGS are added to `env`'s)."""
    if "XLA_FLAGS" in extra:
        extra["XLA_FLAGS"] = f"{env.get('XLA_FLAGS', '')} {extra['XLA_FLAGS']}".strip()
    return subprocess.Popen(
        [*KINETIX, *map(str, args)], env=env | extra, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


def finish(started: list[subprocess.Popen], timeout: float = TIMEOUT) -> list[tuple[int, str]]:
    """Wait for every process (killing all of them if one outlives `timeout`); (exit code, stderr) of each."""
    deadline = time.monotonic() + timeout
    results = []
    try:
        for process in started:
            _, err = process.communicate(timeout=max(deadline - time.monotonic(), 1))
            results.append((process.returncode, err))
    finally:
        for process in started:
            process.kill()
    return results


def processes(args: list, env: dict, count: int = 2) -> list[subprocess.Popen]:
    """The `count` processes of one run of `kinetix ARGS`, coordinated on a free localhost port."""
    flags = ["--coordinator", f"localhost:{free_port()}", "--num-processes", str(count)]
    return [start([*args, *flags, "--process-id", str(i)], env) for i in range(count)]


def run_ok(started: list[subprocess.Popen]) -> None:
    """Wait for the processes; each must succeed."""
    for code, err in finish(started):
        assert code == 0, err[-2000:]
