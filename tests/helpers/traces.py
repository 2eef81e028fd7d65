"""Counting what JAX traces: a call that needs no new compile traces nothing (jax.monitoring's public events)."""

from __future__ import annotations

import contextlib

import jax

TRACE_EVENT = "/jax/core/compile/jaxpr_trace_duration"
"""The event JAX records each time it traces a function to a jaxpr (a new compile, or a cached one's lookup key)."""


@contextlib.contextmanager
def traces():
    """`with traces() as count:` ... `count[0]` is the number of traces JAX made inside the block."""
    count = [0]

    def listener(event: str, duration: float, **_) -> None:
        if event == TRACE_EVENT:
            count[0] += 1

    jax.monitoring.register_event_duration_secs_listener(listener)
    try:
        yield count
    finally:
        jax.monitoring.unregister_event_duration_listener(listener)
