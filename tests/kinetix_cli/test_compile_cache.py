"""The persistent compilation cache of every `kinetix` command (`kinetix_cli.compile_cache`): where it lives, its
switch, and that a damaged entry is compiled again without a word."""

from __future__ import annotations

import subprocess
import warnings
from pathlib import Path

import jax
import pytest

from helpers.processes import KINETIX, process_env
from kinetix_cli import compile_cache
from kinetix_cli.compile_cache import VARIABLE, cache_folder, machine_key, user_folder


def test_the_folder_is_the_users_keyed_by_versions_unless_a_variable_says_otherwise(monkeypatch, tmp_path):
    monkeypatch.delenv(VARIABLE, raising=False)
    monkeypatch.delenv("JAX_COMPILATION_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    key = machine_key()
    assert key.startswith("jax-") and len(key.split("-")[-1]) == 16
    assert cache_folder() == user_folder("jax") == tmp_path / "xdg" / "kinetix" / "jax" / key
    monkeypatch.setenv("JAX_COMPILATION_CACHE_DIR", "")  # JAX's own switch: off when empty
    assert cache_folder() is None
    monkeypatch.setenv(VARIABLE, str(tmp_path / "mine"))  # ours first
    assert cache_folder() == tmp_path / "mine"
    monkeypatch.setenv(VARIABLE, "OFF")
    assert cache_folder() is None


def test_off_writes_nothing_and_leaves_jax_alone(monkeypatch):
    monkeypatch.setattr(compile_cache.os, "environ", {})
    compile_cache.enable(None)
    assert compile_cache.os.environ == {}


def test_jaxs_warning_about_a_damaged_entry_is_not_shown():
    # JAX warns so when an entry does not decompress, then compiles; enabled again on the suite's own folder
    with warnings.catch_warnings(record=True) as caught:
        compile_cache.enable(Path(jax.config.jax_compilation_cache_dir))
        warnings.warn("Error reading persistent compilation cache entry for 'jit_play': error: truncated", stacklevel=1)
        warnings.warn("something else", stacklevel=1)
    assert [str(w.message) for w in caught] == ["something else"]


def play(cache: Path) -> subprocess.CompletedProcess:
    args = [*KINETIX, "validate", "--play", "levels/s/pad-to-pad.json"]
    return subprocess.run(args, env=process_env() | {VARIABLE: str(cache)}, capture_output=True, text=True)


@pytest.mark.slow  # two processes compile an episode (~35 s); make test checks the warning filter above
def test_a_damaged_entry_is_compiled_again_without_a_word(tmp_path):
    first = play(tmp_path / "cache")
    assert first.returncode == 0, first.stderr[-2000:]
    entries = sorted((tmp_path / "cache").glob("*-cache"))
    assert entries  # the episode's program was written
    for i, entry in enumerate(entries):  # torn by a crash, overwritten, emptied
        entry.write_bytes([entry.read_bytes()[:100], b"not a compiled program", b""][i % 3])
    again = play(tmp_path / "cache")
    assert again.returncode == 0 and again.stderr == "", again.stderr[-2000:]
    assert again.stdout == first.stdout


def test_an_entry_without_its_access_time_is_removed_so_jax_can_write_again(tmp_path):
    from jax._src.lru_cache import LRUCache  # the cache JAX writes through with a size bound

    (tmp_path / "kept-cache").write_bytes(b"program")
    (tmp_path / "kept-atime").write_bytes(b"\0" * 8)
    (tmp_path / "unfinished-cache").write_bytes(b"prog")  # its process was killed before it wrote the time
    cache = LRUCache(str(tmp_path), max_size=2**20)
    with pytest.raises(FileNotFoundError):  # JAX reads every entry's time before a write
        cache.put("new", b"program")
    assert compile_cache.remove_unfinished(tmp_path) == [tmp_path / "unfinished-cache"]
    cache.put("new", b"program")
    assert sorted(p.name for p in tmp_path.glob("*-*")) == ["kept-atime", "kept-cache", "new-atime", "new-cache"]
    assert compile_cache.remove_unfinished(tmp_path / "absent") == []
