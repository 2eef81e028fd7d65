"""The options of commands that run on several devices and processes (`pretrain`, `finetune`, `eval`,
`generate`), and `joined`, which starts a command's multi-process part.

One process (the default) uses all its local devices, or `--devices N` of them. Several processes, on one host
or many, each run the same command with `--coordinator HOST:PORT --num-processes P --process-id I` (process 0
listens on PORT); with `KINETIX_DISTRIBUTED=auto` they are found as `jax.distributed` finds them on a cluster
(SLURM, ...). See docs/scaling.md.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

import typer

DEVICES = typer.Option(None, "--devices", min=1, help="Local devices to use per process (default: all).")
COORDINATOR = typer.Option(
    None, "--coordinator", help="HOST:PORT of process 0 of a multi-process run (with --num-processes, --process-id)."
)
NUM_PROCESSES = typer.Option(None, "--num-processes", help="Processes of a multi-process run.")
PROCESS_ID = typer.Option(None, "--process-id", help="This process's index in a multi-process run (0 writes files).")


@contextlib.contextmanager
def joined(coordinator: str | None, num_processes: int | None, process_id: int | None) -> Iterator[None]:
    """Join the multi-process run the options describe (nothing for one process), run the body, then tell the
    other processes this one ended normally."""
    from kinetix_cli import parallel

    parallel.initialize(coordinator, num_processes, process_id)
    try:
        yield
    except BaseException as exc:
        parallel.failed(exc)  # a lost peer: one line, not a traceback (returns for the user's errors)
        raise
    parallel.finish()
