"""The trace cache: a program traced once is read back by a later process (here: with this process's memory of it
cleared) instead of traced again, computes the same bits, and any change of what it depends on is a miss."""

from __future__ import annotations

import dataclasses
import functools
import os
import time

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from flax import struct

from helpers.runs import tiny_config
from kinetix_cli import trace_cache
from kinetix_cli.env.factory import make_env
from kinetix_cli.rl.networks import make_network
from kinetix_cli.rl.ppo import init_runner, ppo_update
from kinetix_cli.trace_cache import cached_jit, compiling

TRACES: list[int] = []
"""One entry per trace of `step`."""
COMPILES: list[str] = []
"""One entry per compile or compile-cache read of this process (jax's monitoring events)."""
jax.monitoring.register_event_listener(
    lambda event, **_: COMPILES.append(event) if "compile_requests" in event else None
)
jax.monitoring.register_event_duration_secs_listener(
    lambda event, seconds, **_: COMPILES.append(event) if event.endswith("backend_compile_duration") else None
)


@struct.dataclass
class State:
    weights: jax.Array
    key: jax.Array
    label: str = struct.field(pytree_node=False, default="state")


@cached_jit(static_argnames=("scale",))
def step(state: State, x: jax.Array, extra=None, *, scale: float = 1.0) -> tuple[State, dict]:
    TRACES.append(1)
    key, noise_key = jax.random.split(state.key)
    y = jnp.tanh(x @ state.weights) * scale + jax.random.normal(noise_key, (x.shape[0], state.weights.shape[1]))
    return State(state.weights + 0.1 * y.mean(), key, state.label), {"sum": y.sum(), "none": None}


@pytest.fixture
def traces(tmp_path):
    """The trace cache in a folder of its own, as a new process would find it; the suite's afterwards."""
    before = trace_cache.folder()
    trace_cache.enable(tmp_path / "traces")
    TRACES.clear()
    yield tmp_path / "traces"
    trace_cache.enable(before)


def inputs():
    return State(jnp.ones((4, 3)), jax.random.key(0)), jnp.arange(8.0).reshape(2, 4)


def equal(a, b):
    """Every leaf of two trees equal bit for bit (keys by their data)."""
    data = lambda x: jax.random.key_data(x) if jnp.issubdtype(x.dtype, jax.dtypes.prng_key) else x  # noqa: E731
    jax.tree.map(lambda x, y: np.testing.assert_array_equal(data(x), data(y)), a, b)


def test_a_program_traced_once_is_read_back_and_computes_the_same_bits(traces):
    state, x = inputs()
    first = step(state, x, scale=2.0)
    assert len(TRACES) == 1 and len(list(traces.glob("*.trace"))) == 1
    trace_cache.enable(traces)  # a new process: nothing in memory, the entry on disk
    again = step(state, x, scale=2.0)
    assert len(TRACES) == 1, "read back, not traced"
    equal(first, again)
    assert again[0].label == "state" and again[1]["none"] is None  # the output's structure, static fields included
    equal(again, step.jitted(state, x, scale=2.0))  # what jax.jit computes


def test_a_change_of_what_the_trace_depends_on_traces_again(traces, monkeypatch):
    state, x = inputs()
    step(state, x)
    step(state, x, scale=3.0)  # a static argument
    step(state, x[:1])  # a shape
    step(state, x.astype(jnp.int32))  # a dtype
    step(state, x, jnp.ones(2))  # a traced argument more
    assert len(TRACES) == 5 and len(list(traces.glob("*.trace"))) == 5
    monkeypatch.setattr(trace_cache, "process_key", lambda: "other source")
    trace_cache.enable(traces)
    step(state, x)
    assert len(TRACES) == 6


def test_a_damaged_entry_is_traced_again_and_rewritten(traces):
    state, x = inputs()
    first = step(state, x)
    (entry,) = traces.glob("*.trace")
    entry.write_bytes(b"not a trace")
    trace_cache.enable(traces)
    equal(step(state, x), first)
    assert len(TRACES) == 2
    trace_cache.enable(traces)
    step(state, x)
    assert len(TRACES) == 2, "the rewritten entry is read back"


def test_an_equal_network_built_after_other_modules_has_the_same_key():
    """flax numbers the modules a process builds; a key must not see the number (else a test suite, where each
    test builds other networks first, never reads a trace back)."""
    config = tiny_config()
    first = trace_cache.static_bytes({"network": make_network(config.model, config.env), "scale": 2.0})
    for _ in range(3):
        make_network(config.model, config.env)
    assert trace_cache.static_bytes({"network": make_network(config.model, config.env), "scale": 2.0}) == first
    wider = dataclasses.replace(config.model, width=config.model.width + 1)
    assert trace_cache.static_bytes({"network": make_network(wider, config.env), "scale": 2.0}) != first


def test_inside_another_trace_or_off_it_is_jax_jit(traces):
    state, x = inputs()
    jax.jit(lambda s, x: step(s, x)[1]["sum"])(state, x)  # part of the outer program
    assert len(TRACES) == 1 and not traces.exists()
    trace_cache.enable(None)
    step(state, x[:1])  # a shape not traced before in this process
    assert len(TRACES) == 2 and not traces.exists()


def test_the_folder_keeps_the_most_recently_used_entries_within_its_bound(traces, monkeypatch):
    state, x = inputs()
    step(state, x)
    (entry,) = traces.glob("*.trace")
    monkeypatch.setattr(trace_cache, "MAX_BYTES", entry.stat().st_size + 1)
    step(state, x, scale=5.0)  # a second entry: the first, older, goes
    assert len(list(traces.glob("*.trace"))) == 1 and not entry.exists()


def test_a_training_update_read_back_computes_what_jax_jit_computes(traces, tiny_pool):
    config = tiny_config()
    env, env_params = make_env(config.env)
    network = make_network(config.model, config.env)
    runner = init_runner(env, network, config.ppo, tiny_pool, jax.random.key(0))
    parts = {"env": env, "network": network, "settings": config.ppo}
    ppo_update(runner, env_params, tiny_pool, **parts)
    trace_cache.enable(traces)
    equal(ppo_update(runner, env_params, tiny_pool, **parts), ppo_update.jitted(runner, env_params, tiny_pool, **parts))


@pytest.mark.parametrize("on, scale", [(True, 7.0), (False, 8.0)], ids=["traces", "no traces"])
def test_programs_loaded_together_are_what_their_calls_run(traces, on, scale):
    """`compiling` compiles (or reads from the compile cache) the programs the calls that follow run: the calls
    compile nothing more, and compute what `jax.jit` computes. A call it cannot lower is left to raise itself. Each
    case's own `scale`: programs no other test compiled."""
    trace_cache.enable(traces if on else None)
    state, x = inputs()
    calls = [functools.partial(step, state, x, scale=scale), functools.partial(step, state, x[:1], scale=scale)]
    with compiling(*calls, functools.partial(step, state)):  # a missing argument: nothing loaded, nothing raised
        pass
    loaded = len(COMPILES)
    got = [call() for call in calls]
    assert len(COMPILES) == loaded, "the calls compiled again"
    for call, out in zip(calls, got, strict=True):
        equal(out, step.jitted(*call.args, **call.keywords))
    with pytest.raises(TypeError):
        step(state)


def test_a_write_stopped_before_its_rename_leaves_nothing_for_long(traces):
    traces.mkdir(parents=True)
    stopped, live = traces / ".stopped.tmp", traces / ".live.tmp"
    stopped.write_bytes(b"half an entry")
    live.write_bytes(b"being written")
    hours_ago = time.time() - 2 * trace_cache.STALE_SECONDS
    os.utime(stopped, (hours_ago, hours_ago))
    state, x = inputs()
    step(state, x)  # a write
    assert not stopped.exists() and live.exists()


def test_the_traces_live_in_the_compile_cache_folder_unless_switched_off(monkeypatch, tmp_path):
    monkeypatch.delenv(trace_cache.VARIABLE, raising=False)
    assert trace_cache.folder_in(tmp_path) == tmp_path / "traces" and trace_cache.folder_in(None) is None
    monkeypatch.setenv(trace_cache.VARIABLE, "off")
    assert trace_cache.folder_in(tmp_path) is None
