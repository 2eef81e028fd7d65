"""Messages tell the truth: user text prints as it is (no markup), versions are checked before fields, and each
error says what is wrong and where."""

from __future__ import annotations

import json
import shutil

import yaml

from helpers.cli import kinetix
from helpers.levels import CAR
from helpers.paths import REFERENCE_LEVELS
from helpers.runs import EVAL_LEVEL, TINY, set_args


def test_bracketed_file_names_print_whole(capsys, tmp_path):
    draft = tmp_path / "[draft].json"
    shutil.copy("levels/s/pad-to-pad.json", draft)
    result = kinetix(capsys, "validate", draft)
    assert result.code == 0 and f"ok {draft}" in result.out
    missing = tmp_path / "[gone].json"
    assert f"{missing}: no such file" in kinetix(capsys, "render", missing, "-o", tmp_path / "x.png").error_line


def test_bracketed_values_print_whole(capsys, tmp_path):
    (tmp_path / "car.json").write_text(json.dumps(CAR | {"gravity": [1]}))
    assert "gravity: must be [x, y], got [1]" in kinetix(capsys, "validate", tmp_path / "car.json").error_line
    line = kinetix(
        capsys, "pretrain", "--config", "experiments/cpu-small.yaml", "--run-dir", tmp_path / "r",
        "--set", "levels.files=[a.json]",
    ).error_line  # fmt: skip
    assert "levels.files: is only used when levels.source is 'files' (got ('a.json',))" in line


def test_a_future_level_version_is_named_before_its_new_keys(capsys, tmp_path):
    (tmp_path / "v2.json").write_text(json.dumps(CAR | {"format": "kinetix-level/2", "wind": [1, 0]}))
    line = kinetix(capsys, "validate", tmp_path / "v2.json").error_line
    assert 'format: this kinetix reads "kinetix-level/1" only, got "kinetix-level/2"' in line and "wind" not in line


def test_a_level_too_big_says_what_is_too_many(capsys, tmp_path):
    bodies = [{"name": f"b{i}", "shape": "circle", "radius": 0.1, "position": [0.3 + 0.3 * i, 1]} for i in range(6)]
    (tmp_path / "big.json").write_text(json.dumps({"format": "kinetix-level/1", "bodies": bodies}))
    line = kinetix(capsys, "validate", tmp_path / "big.json").error_line
    assert "too big for size l, the largest: scene: circles: has 6 but the size holds 4" in line


def test_warnings_are_one_line_each_without_markup(capsys, tmp_path):
    shutil.copy(REFERENCE_LEVELS / "m" / "arm_up.json", tmp_path / "[ref].json")  # a conversion with notes
    result = kinetix(capsys, "validate", tmp_path / "[ref].json")
    warnings = [line for line in result.err.splitlines() if line]
    assert result.code == 0 and warnings
    assert all(line.startswith(f"warning: {tmp_path}/[ref].json: ") for line in warnings)


def test_integer_bounds_print_as_integers(capsys, tmp_path):
    args = ["pretrain", "--config", "experiments/cpu-small.yaml", "--run-dir", tmp_path / "r"]
    line = kinetix(capsys, *args, "--set", "run.seed=-1").error_line
    assert "run.seed: must be >= 0 and <= 2147482623 (got -1)" in line
    line = kinetix(capsys, *args, "--set", "curriculum.refresh_every=0").error_line
    assert "curriculum.refresh_every: must be >= 1 and <= 2147483647 (got 0)" in line
    line = kinetix(capsys, *args, "--set", "curriculum.buffer_share=0").error_line
    assert "curriculum.buffer_share: must be > 0 and <= 1 (got 0.0)" in line  # a float bound stays short


def test_finetune_from_a_run_of_another_model_names_the_flag(capsys, tmp_path, tiny_run):
    finetune = ["finetune", EVAL_LEVEL, "--config", "experiments/cpu-small.yaml", *set_args(TINY)]
    other = shutil.copytree(tiny_run, tmp_path / "other")  # its checkpoint holds another model than its config says
    config = yaml.safe_load((other / "config.yaml").read_text())
    config["model"]["width"] = 32
    (other / "config.yaml").write_text(yaml.safe_dump(config))
    line = kinetix(capsys, *finetune, "--from", other, "--run-dir", tmp_path / "a").error_line
    assert line.startswith(f"error: --from {other}/checkpoints/6: its parameters do not fit the model")
    line = kinetix(
        capsys, *finetune, "--from", tiny_run, "--run-dir", tmp_path / "b", "--set", "model.width=32"
    ).error_line
    assert line.startswith(
        f"error: --from {tiny_run}: the checkpoint's network does not match this run's model settings"
    )
    assert line.endswith("float32[16] found)")  # the first leaf that differs: width 32 wanted, the run's 16 found
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


def test_the_buffer_of_a_run_without_one_names_its_curriculum(capsys, tmp_path, tiny_run):
    # here, not beside the SFL run's tests: their worker would train the tiny run for this alone
    line = kinetix(capsys, "levels", "show", tiny_run, "--buffer", "-o", tmp_path / "x.png").error_line
    assert "holds no level buffer (the run's curriculum.name is 'dr')" in line
