"""Level sets: a finished set is verified when its command is rerun, a killed write's temporaries never block or
linger, and every manifest field is checked on load."""

from __future__ import annotations

import json
import re

import pytest

from helpers.cli import kinetix
from helpers.levelsets import small_levelset
from kinetix_cli.errors import UserError
from kinetix_cli.levels.levelset import load_levelset


@pytest.fixture
def levelset(tmp_path):
    out = tmp_path / "set"
    small_levelset(out)
    return out


def test_rerunning_a_finished_set_with_a_damaged_shard_fails(levelset):
    shard = levelset / "shard-00001.npz"
    raw = bytearray(shard.read_bytes())
    raw[100] ^= 0xFF
    shard.write_bytes(bytes(raw))
    with pytest.raises(UserError, match="shard-00001.npz: sha256 does not match the manifest"):
        small_levelset(levelset)  # the same command again: it used to report the set as written


def test_a_killed_writes_temporaries_are_cleaned_and_do_not_block_the_rerun(tmp_path):
    out = tmp_path / "set"
    out.mkdir()
    (out / ".shard-00000.npz.k1ll3d.tmp").write_bytes(b"half a shard")  # killed before its first shard landed
    small_levelset(out)
    assert sorted(p.name for p in out.iterdir()) == ["manifest.json", "shard-00000.npz", "shard-00001.npz"]


def test_a_killed_write_mid_set_resumes_to_the_same_files(tmp_path):
    whole, cut = tmp_path / "whole", tmp_path / "cut"
    small_levelset(whole)
    small_levelset(cut)
    (cut / "manifest.json").unlink()  # as if killed after the last shard, before the manifest
    progress = json.loads((whole / "manifest.json").read_text())
    progress |= {"format": "kinetix-levelset-progress/1", "next_chunk": 1, "offset": 0}
    (cut / "progress.json").write_text(json.dumps(progress))
    (cut / ".manifest.json.x.tmp").write_text("{")
    small_levelset(cut)
    assert {p.name: p.read_bytes() for p in cut.iterdir()} == {p.name: p.read_bytes() for p in whole.iterdir()}


MANIFEST_BREAKS = [
    (lambda m: m.update(shards=[]), "shards: expected a non-empty list"),
    (lambda m: m.pop("shards"), "shards: expected a non-empty list"),
    (lambda m: m.pop("seed"), "seed: missing or not an integer"),
    (lambda m: m.pop("stats"), "stats: missing or not an object"),
    (lambda m: m["shards"][0].pop("sha256"), "shards[0]: expected"),
    (lambda m: m["shards"][0].update(file="../escape.npz"), "shards[0]: expected"),
    (lambda m: m.update(count=99), "count: 99 is not the sum of the shard counts"),
    (lambda m: m.update(size="xl"), "size: expected one of s, m, l"),
    (lambda m: m.update(format="kinetix-levelset/2"), "format: expected 'kinetix-levelset/1'"),
]


@pytest.mark.parametrize(("breaks", "message"), MANIFEST_BREAKS, ids=lambda x: x[:30] if isinstance(x, str) else "edit")
def test_a_broken_manifest_is_one_line_in_every_command(capsys, tmp_path, levelset, breaks, message):
    manifest = json.loads((levelset / "manifest.json").read_text())
    breaks(manifest)
    (levelset / "manifest.json").write_text(json.dumps(manifest))
    for args in (["levels", "info", levelset], ["levels", "show", levelset, "-o", tmp_path / "x.png"]):
        assert message in kinetix(capsys, *args).error_line
    with pytest.raises(UserError, match=re.escape(message)):
        load_levelset(levelset)


def test_a_level_set_is_not_taken_for_level_files(capsys, levelset):
    line = kinetix(capsys, "validate", levelset).error_line
    assert "a generated level set, not level files" in line
