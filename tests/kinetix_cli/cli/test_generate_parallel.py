"""`kinetix generate` across devices and processes writes the level set of one device: the same files, byte for
byte (each device computes whole chunks, so no chunk depends on the device count)."""

from __future__ import annotations

import pytest

from helpers.processes import FORCE_2, cache_env, processes, run_ok, start

GENERATE = ["generate", "--size", "s", "--count", "40", "--seed", "4", "--chunk", "16", "--shard-size", "12"]
GENERATE += ["--filter", "noop"]  # the filter episodes run (their rounding is what could differ), one compile


@pytest.fixture(scope="module")
def env(tmp_path_factory):
    return cache_env(tmp_path_factory.mktemp("jax-cache"))


def files(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


@pytest.fixture(scope="module")
def one_device_set(tmp_path_factory, env):
    out = tmp_path_factory.mktemp("generate") / "one"
    run_ok([start([*GENERATE, "--out", out], env)])
    assert sorted(files(out)) == ["manifest.json"] + [f"shard-0000{i}.npz" for i in range(4)]  # both processes write
    return out


def test_two_processes_write_the_set_of_one_device(tmp_path, env, one_device_set):
    run_ok(processes([*GENERATE, "--out", tmp_path / "two-processes"], env))
    assert files(tmp_path / "two-processes") == files(one_device_set)


@pytest.mark.slow
def test_two_devices_write_the_set_of_one(tmp_path, env, one_device_set):
    run_ok([start([*GENERATE, "--out", tmp_path / "two-devices"], env, XLA_FLAGS=FORCE_2)])
    assert files(tmp_path / "two-devices") == files(one_device_set)
