"""`kinetix` splits the CPU into one JAX device per core (at most 4), or `KINETIX_CPU_DEVICES` of them, unless a
count is chosen for JAX itself; training on a default split uses the most devices its batches split over. Each
split is checked in a fresh process: a process's device count is fixed once JAX starts."""

from __future__ import annotations

import subprocess
import sys

import jax
import pytest

from helpers.cli import kinetix
from helpers.processes import FORCE_2, process_env
from kinetix_cli import cpu
from kinetix_cli.errors import UserError


def split_in_a_process(script: str, **env: str) -> list[str]:
    """The lines `script` prints in a fresh Python process whose environment has no CPU device count but `env`."""
    base = {k: v for k, v in process_env().items() if k not in (cpu.VARIABLE, cpu.JAX_VARIABLE, "XLA_FLAGS")}
    done = subprocess.run([sys.executable, "-c", script], env=base | env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout.splitlines()


def test_a_default_split_is_one_device_per_core_and_training_uses_the_devices_its_batches_split_over():
    script = """
import warnings
from kinetix_cli import cpu
cpu.usable_cores = lambda: 3
print(cpu.split())
import jax
from kinetix_cli.parallel import fitting_devices
print(jax.local_device_count(), jax.devices()[0].platform, cpu.automatic())
print(fitting_devices({"ppo.num_envs": 6}))
with warnings.catch_warnings(record=True) as seen:
    warnings.simplefilter("always")
    print(fitting_devices({"ppo.num_envs": 4, "clone.batch": 6}))
print(*(w.message for w in seen))
"""
    assert split_in_a_process(script) == [
        "3",
        "3 cpu 3",
        "3",
        "2",
        "ppo.num_envs 4 does not split over the 3 CPU devices (one per core); using 2",
    ]


def test_the_default_is_one_device_per_core_up_to_four(monkeypatch):
    for cores, devices in ((1, 1), (2, 2), (16, 4)):
        monkeypatch.setattr(cpu, "usable_cores", lambda cores=cores: cores)
        assert cpu.default_count() == devices


def test_a_chosen_count_is_kept_and_a_multi_process_run_undoes_the_default_split():
    script = """
from kinetix_cli import cpu
print(cpu.split())
import jax
print(jax.local_device_count(), cpu.automatic())
"""
    assert split_in_a_process(script, KINETIX_CPU_DEVICES="2") == ["2", "2 None"]  # the user's count: no fallback
    assert split_in_a_process(script, KINETIX_CPU_DEVICES="3", XLA_FLAGS=FORCE_2) == ["None", "2 None"]
    undone = """
import os
from kinetix_cli import cpu
cpu.usable_cores = lambda: 2
cpu.split()
cpu.unsplit()
import jax
print(jax.local_device_count(), cpu.JAX_VARIABLE in os.environ)
"""
    assert split_in_a_process(undone) == ["1 False"]  # nor do the processes it starts inherit it


def test_a_bad_count_is_one_line(capsys, monkeypatch):
    for bad in ("0", "two", "-1"):
        monkeypatch.setenv(cpu.VARIABLE, bad)
        with pytest.raises(UserError, match=f"KINETIX_CPU_DEVICES='{bad}': expected a whole number"):
            cpu.split()
    assert "error: KINETIX_CPU_DEVICES='-1': expected a whole number" in kinetix(capsys, "agents").error_line
    monkeypatch.setenv(cpu.VARIABLE, "2")
    jax.devices()
    assert cpu.split() is None and jax.local_device_count() == 1  # JAX has started here: its devices are fixed
