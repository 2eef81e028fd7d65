"""Level sets on disk: round trip, byte-reproducible and resumable generation, duplicates, verified loading."""

from __future__ import annotations

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from engine import SIZES
from kinetix_cli.bench.env import random_levels
from kinetix_cli.errors import UserError
from kinetix_cli.levels.levelset import (
    LEVELSET_FORMAT,
    PROGRESS_FILE,
    generate_levelset,
    level_at,
    level_digests,
    load_levelset,
    to_arrays,
    write_npz,
)

POOL_SIZE = 40
CHUNK = 8
SETTINGS = {"generator": {"kind": "random"}, "filter": {"noop_steps": 0}}


@pytest.fixture(scope="module")
def pool():
    """POOL_SIZE distinct size-s levels with numpy leaves."""
    levels = jax.tree.map(np.asarray, random_levels(SIZES["s"], POOL_SIZE, seed=3))
    assert len(set(level_digests(to_arrays(levels)))) == POOL_SIZE
    return levels


def take(pool, rows):
    return jax.tree.map(lambda x: x[np.asarray(rows, dtype=int)], pool)


class Chunks:
    """A stand-in sampler: chunk i draws CHUNK levels from the pool (with repeats) and keeps a random subset;
    raises on chunk `fail_at`; records the chunks asked for."""

    def __init__(self, pool, fail_at: int | None = None):
        self.pool, self.fail_at, self.calls = pool, fail_at, []

    def __call__(self, i: int):
        self.calls.append(i)
        if i == self.fail_at:
            raise RuntimeError(f"killed at chunk {i}")
        rng = np.random.default_rng(i)
        rows = rng.integers(0, POOL_SIZE, CHUNK)
        kept = rows[rng.uniform(size=CHUNK) < 0.6]
        return take(self.pool, kept), {"sampled": CHUNK, "dropped_random": CHUNK - len(kept)}


def generate(out, chunk_fn, **overrides):
    args = dict(size="s", count=20, seed=0, settings=SETTINGS, shard_size=6) | overrides
    return generate_levelset(out, chunk_fn=chunk_fn, **args)


def files(directory):
    return {p.name: p.read_bytes() for p in sorted(directory.iterdir())}


def assert_levels_equal(a, b):
    for x, y in zip(jax.tree.leaves(a), jax.tree.leaves(b), strict=True):
        np.testing.assert_array_equal(x, y)


def test_round_trip(tmp_path, pool):
    manifest = generate(tmp_path, Chunks(pool))
    assert sorted(files(tmp_path)) == ["manifest.json", *(f"shard-0000{k}.npz" for k in range(4))]
    assert [s["count"] for s in manifest["shards"]] == [6, 6, 6, 2]
    assert manifest["format"] == LEVELSET_FORMAT and manifest["settings"] == SETTINGS
    loaded = load_levelset(tmp_path)
    assert loaded.manifest == manifest == json.loads((tmp_path / "manifest.json").read_text())
    assert_levels_equal(loaded.levels, take(pool, first_distinct_rows(20)))
    assert_levels_equal(level_at(loaded, 7), jax.tree.map(lambda x: x[7], loaded.levels))


def first_distinct_rows(count):
    """Reference: the pool rows of the first `count` distinct levels the chunks yield, in order."""
    rows, i = [], 0
    while len(rows) < count:
        rng = np.random.default_rng(i)
        drawn = rng.integers(0, POOL_SIZE, CHUNK)
        for row in drawn[rng.uniform(size=CHUNK) < 0.6]:
            rows += [] if row in rows else [row]
        i += 1
    return rows[:count]


def test_write_npz_is_byte_identical_and_loadable(tmp_path, pool):
    arrays = to_arrays(pool)
    for name in ("a.npz", "b.npz"):
        with open(tmp_path / name, "wb") as f:
            write_npz(f, arrays)
    assert (tmp_path / "a.npz").read_bytes() == (tmp_path / "b.npz").read_bytes()
    with np.load(tmp_path / "a.npz") as npz:
        np.testing.assert_array_equal(npz["physics/bodies/position"], arrays["physics/bodies/position"])


def test_reruns_are_byte_identical(tmp_path, pool):
    generate(tmp_path / "a", Chunks(pool))
    generate(tmp_path / "b", Chunks(pool))
    assert files(tmp_path / "a") == files(tmp_path / "b")


@pytest.mark.parametrize("fail_at", [1, 3, 5], ids=["before-any-shard", "at-a-chunk-boundary", "inside-a-chunk"])
def test_resume_after_crash_equals_uninterrupted(tmp_path, pool, fail_at):
    generate(tmp_path / "whole", Chunks(pool))
    with pytest.raises(RuntimeError, match="killed"):
        generate(tmp_path / "resumed", Chunks(pool, fail_at=fail_at))
    progress = json.loads((tmp_path / "resumed" / PROGRESS_FILE).read_text())
    assert (progress["offset"] > 0) == (fail_at == 5)
    second = Chunks(pool)
    generate(tmp_path / "resumed", second)
    assert second.calls[0] == progress["next_chunk"]
    assert files(tmp_path / "resumed") == files(tmp_path / "whole")


def test_duplicates_are_dropped_and_counted(tmp_path, pool):
    def chunk_fn(i):  # level i twice, then level i - 1 again
        rows = [i, i] + ([i - 1] if i else [])
        return take(pool, rows), {"sampled": len(rows)}

    manifest = generate(tmp_path, chunk_fn, count=5, shard_size=2)
    assert manifest["stats"] == {"duplicates": 1 + 2 * 3, "sampled": 2 + 3 * 4}  # chunk 4 stops at its first row
    assert_levels_equal(load_levelset(tmp_path).levels, take(pool, range(5)))


def test_finished_set_is_a_no_op_and_progress_is_reported(tmp_path, pool):
    seen = []
    manifest = generate(tmp_path, Chunks(pool), progress=lambda kept, stats: seen.append((kept, stats["sampled"])))
    assert seen[-1][0] == 20 and seen == sorted(seen) and not (tmp_path / PROGRESS_FILE).exists()
    never = Chunks(pool, fail_at=0)
    assert generate(tmp_path, never) == manifest and never.calls == []


@pytest.mark.parametrize(
    ("field", "value"), [("seed", 1), ("count", 21), ("size", "m"), ("settings", {"generator": {"kind": "x"}})]
)
@pytest.mark.parametrize("finished", [True, False])
def test_a_different_set_in_the_directory_is_refused(tmp_path, pool, field, value, finished):
    if finished:
        generate(tmp_path, Chunks(pool))
    else:
        with pytest.raises(RuntimeError):
            generate(tmp_path, Chunks(pool, fail_at=2))
    before = files(tmp_path)
    with pytest.raises(UserError, match=rf"{tmp_path}.*{field}="):
        generate(tmp_path, Chunks(pool), **{field: value})
    assert files(tmp_path) == before


def test_a_foreign_directory_is_refused(tmp_path, pool):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(UserError, match="not a level set"):
        generate(tmp_path, Chunks(pool))


def flip_byte(path):
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))


@pytest.mark.parametrize(
    ("damage", "message"),
    [
        (flip_byte, "sha256"),
        (lambda p: p.write_bytes(p.read_bytes()[:100]), "sha256"),
        (lambda p: p.unlink(), "missing"),
    ],
)
def test_a_damaged_shard_is_a_user_error(tmp_path, pool, damage, message):
    generate(tmp_path, Chunks(pool))
    damage(tmp_path / "shard-00002.npz")
    with pytest.raises(UserError, match=rf"shard-00002\.npz.*{message}"):
        load_levelset(tmp_path)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda m: m | {"format": "kinetix-levelset/0"}, "format"),
        (lambda m: m | {"count": 19}, "count"),
        (lambda m: m | {"size": "xl"}, "size"),
        (lambda m: m | {"shards": [{"file": "../x.npz", "count": 20, "sha256": ""}]}, r"shards\[0\]"),
    ],
)
def test_a_bad_manifest_is_a_user_error(tmp_path, pool, edit, message):
    generate(tmp_path, Chunks(pool))
    path = tmp_path / "manifest.json"
    path.write_text(json.dumps(edit(json.loads(path.read_text()))))
    with pytest.raises(UserError, match=rf"manifest\.json: {message}"):
        load_levelset(tmp_path)


def test_an_unfinished_set_cannot_be_loaded(tmp_path, pool):
    with pytest.raises(RuntimeError):
        generate(tmp_path, Chunks(pool, fail_at=3))
    with pytest.raises(UserError, match="manifest.json: not found.*resume"):
        load_levelset(tmp_path)


@pytest.mark.parametrize("index", [-1, 20])
def test_a_bad_index_is_a_user_error(tmp_path, pool, index):
    generate(tmp_path, Chunks(pool))
    with pytest.raises(UserError, match=r"--index: .*0\.\.19"):
        level_at(load_levelset(tmp_path), index)


def test_empty_chunks_and_device_arrays_are_accepted(tmp_path, pool):
    def chunk_fn(i):  # odd chunks keep nothing; leaves are jax arrays, as a jitted sampler returns
        return jax.tree.map(jnp.asarray, take(pool, [] if i % 2 else [i // 2])), {"sampled": 1}

    manifest = generate(tmp_path, chunk_fn, count=3)
    assert manifest["stats"] == {"duplicates": 0, "sampled": 5}
    assert_levels_equal(load_levelset(tmp_path).levels, take(pool, range(3)))


def test_a_chunk_of_another_size_is_a_programming_error(tmp_path, pool):
    with pytest.raises(ValueError, match=r"chunk_fn\(0\).*physics/bodies/position"):
        generate(tmp_path, Chunks(pool), size="m")


def test_filters_that_keep_nothing_stop_with_a_user_error(tmp_path, pool):
    from kinetix_cli.levels.levelset import MAX_IDLE_CHUNKS

    calls = []

    def only_repeats(i):  # one level, then the same level again and again: nothing new after chunk 0
        calls.append(i)
        return take(pool, [0]), {"sampled": 1}

    with pytest.raises(UserError, match="kept no new level"):
        generate(tmp_path, only_repeats, count=2)
    assert len(calls) == MAX_IDLE_CHUNKS + 1
