"""Bad files are one line naming the file (and field), exit code 2, in every command that reads them: not UTF-8,
not JSON, nested too deep, huge literals and texts, special files, reference files with missing or wrongly typed
fields, broken experiment configs."""

from __future__ import annotations

import json
import os

import pytest

from helpers.cli import kinetix
from helpers.levels import CAR
from helpers.paths import REFERENCE_LEVELS

READERS = [
    ["validate", "{L}"],
    ["render", "{L}", "-o", "{TMP}/x.png"],
    ["rollout", "{L}", "--policy", "noop"],
    ["levels", "list", "{L}"],
    ["levels", "sheet", "{L}", "-o", "{TMP}/x.png"],
    ["solve", "{L}"],
    ["finetune", "{L}", "--from", "none", "--config", "experiments/cpu-small.yaml", "--run-dir", "{TMP}/run"],
    ["import", "{L}", "-o", "{TMP}/imported"],
]

BAD_CONTENT = {
    "not UTF-8": (b'{"format": "kinetix-level/1", "name": "caf\xe9"}', "not UTF-8 text"),
    "not JSON": (b"{'format': 'kinetix-level/1'}", "not valid JSON"),
    "truncated": (json.dumps(CAR).encode()[:-20], "not valid JSON"),
    "nested too deep": (b"[" * 100_000 + b"]" * 100_000, "nested too deeply"),
    "huge integer": (b'{"format": "kinetix-level/1", "bodies": [' + b"9" * 5000 + b"]}", "not readable JSON"),
    "empty": (b"", "not valid JSON"),
    "a list": (b"[1, 2, 3]", "must be a JSON object"),
}


@pytest.mark.parametrize("args", READERS, ids=lambda a: " ".join(a[:2]))
@pytest.mark.parametrize("kind", list(BAD_CONTENT))
def test_bad_level_files_are_one_line_everywhere(capsys, tmp_path, args, kind):
    content, message = BAD_CONTENT[kind]
    level = tmp_path / "bad.json"
    level.write_bytes(content)
    if args[0] == "import" and kind == "a list":  # import reads only the reference format
        message = "not a reference-format level"
    line = kinetix(capsys, *(a.format(L=level, TMP=tmp_path) for a in args)).error_line
    assert str(level) in line and message in line
    assert not (tmp_path / "run").exists() and not (tmp_path / "imported").exists()


def test_special_and_huge_files_are_refused(capsys, tmp_path):
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    assert "is a special file, not a JSON file" in kinetix(capsys, "validate", fifo).error_line
    big = tmp_path / "big.json"
    with open(big, "wb") as f:
        f.truncate(65 * 2**20)
    assert "JSON files are read up to" in kinetix(capsys, "validate", big).error_line


def test_long_texts_are_refused_with_their_length(capsys, tmp_path):
    (tmp_path / "long.json").write_text(json.dumps(CAR | {"description": "x" * 50_000}))
    assert "description: at most 2000 characters, got 50,000" in kinetix(capsys, "validate", tmp_path).error_line
    (tmp_path / "long.json").write_text(json.dumps(CAR | {"name": "n" * 1000}))
    assert "name: at most 200 characters, got 1,000" in kinetix(capsys, "validate", tmp_path).error_line


REFERENCE_BREAKS = [
    (lambda d: d["env_state"]["polygon"][4].pop("density"), "env_state.polygon[4].density: missing"),
    (lambda d: d["env_state"]["polygon"][4].update(density="heavy"), 'must be a finite number, got "heavy"'),
    (lambda d: d["env_state"]["polygon"][0].pop("vertices"), "env_state.polygon[0].vertices: missing"),
    (lambda d: d["env_state"].update(joint=5), "env_state.joint: must be a list of objects"),
    (lambda d: d["env_state"]["joint"][0].pop("active"), "env_state.joint[0].active: missing"),
    (lambda d: d.update(static_env_params=3), "static_env_params: must be an object, got 3"),
    (lambda d: d["env_state"].update(collision_matrix={"0": 1}), "collision_matrix: must be a"),
]


@pytest.mark.parametrize(
    ("breaks", "message"), REFERENCE_BREAKS, ids=lambda x: x[:30] if isinstance(x, str) else "edit"
)
def test_reference_files_with_missing_or_mistyped_fields(capsys, tmp_path, breaks, message):
    data = json.loads((REFERENCE_LEVELS / "s" / "h2_one_wheel_car.json").read_text())
    breaks(data)
    (tmp_path / "ref.json").write_text(json.dumps(data))
    line = kinetix(capsys, "validate", tmp_path / "ref.json").error_line
    assert message in line and "ref.json" in line


BAD_CONFIGS = {
    "not UTF-8": (b"ppo:\n  lr: \xff\n", "cannot read"),
    "bad YAML": (b"ppo: [unclosed\n", "invalid YAML"),
    "a list": (b"- 1\n- 2\n", "expected a mapping of sections"),
    "future format": (b"format: kinetix-experiment/2\nnewsection: {a: 1}\n", "format: expected 'kinetix-experiment/1'"),
    "duplicate key": (b"ppo:\n  lr: 1e-4\n  lr: 2e-4\n", "duplicate key 'lr'"),
}


@pytest.mark.parametrize("kind", list(BAD_CONFIGS))
def test_bad_experiment_files_are_one_line(capsys, tmp_path, kind):
    content, message = BAD_CONFIGS[kind]
    (tmp_path / "exp.yaml").write_bytes(content)
    line = kinetix(capsys, "pretrain", "--config", tmp_path / "exp.yaml", "--run-dir", tmp_path / "run").error_line
    assert "exp.yaml" in line and message in line and not (tmp_path / "run").exists()


def test_a_folder_as_config_is_one_line(capsys, tmp_path):
    line = kinetix(capsys, "pretrain", "--config", tmp_path, "--run-dir", tmp_path / "run").error_line
    assert str(tmp_path) in line
