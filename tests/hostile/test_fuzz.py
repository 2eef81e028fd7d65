"""Property-based fuzzing of the parsers (hypothesis): any mutation of a valid level file, reference-format level or
experiment config yields a valid object or one clean `UserError` line, never another exception."""

from __future__ import annotations

import copy
import json

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers.levels import CAR, FALL, PUSH
from helpers.paths import EXPERIMENTS, LEVELS, REFERENCE_LEVELS
from kinetix_cli.config import load_config
from kinetix_cli.errors import UserError
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.reference import convert_reference_level

FUZZ = settings(deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True)
"""Examples per parser: 300, or 100 in `make test` (-m "not slow"): the profile tests/conftest.py loads."""

SCALARS = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=12),
    st.sampled_from(["", "auto", "box", "circle", "polygon", "green", "red", "fixed", "kinetix-level/1", "s", "l"]),
)
VALUES = st.recursive(
    SCALARS,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=12,
)


def _paths(node, prefix=()):
    """Every path (tuple of keys and indices) into a JSON value, the root included."""
    yield prefix
    if isinstance(node, dict):
        for key, value in node.items():
            yield from _paths(value, (*prefix, key))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from _paths(value, (*prefix, i))


@st.composite
def mutated(draw, bases):
    """A base JSON value with 1-3 mutations: a node replaced, deleted, or wrapped in a list."""
    data = copy.deepcopy(draw(st.sampled_from(bases)))
    for _ in range(draw(st.integers(1, 3))):
        paths = list(_paths(data))
        path = draw(st.sampled_from(paths))
        if not path:
            if draw(st.booleans()):
                data = draw(VALUES)
            continue
        parent = data
        for key in path[:-1]:
            parent = parent[key]
        key = path[-1]
        action = draw(st.sampled_from(["replace", "delete", "wrap", "number"]))
        if action == "delete" and isinstance(parent, dict):
            del parent[key]
        elif action == "wrap":
            parent[key] = [parent[key]]
        elif action == "number":
            parent[key] = draw(st.sampled_from([0, -1, 1e39, -1e30, 1e-45, 2**64, float("inf"), float("nan"), 10**400]))
        else:
            parent[key] = draw(VALUES)
    return data


LEVEL_BASES = [CAR, FALL, PUSH] + [json.loads(p.read_text()) for p in sorted(LEVELS.glob("[sm]/*.json"))[:6]]


@FUZZ
@given(mutated(LEVEL_BASES))
def test_mutated_level_files_parse_or_fail_in_one_line(data):
    try:
        spec = parse_level(data, "fuzz.json")
    except UserError as exc:
        assert "\n" not in str(exc) and str(exc).startswith("fuzz.json: ")
        return
    spec.build()  # a parsed level always builds at its size


def _reference_bases():
    if not REFERENCE_LEVELS.is_dir():
        pytest.fail(f"{REFERENCE_LEVELS} is missing: run `make reference-levels` (make test does)")
    return [json.loads(p.read_text()) for p in sorted(REFERENCE_LEVELS.glob("s/*.json"))[:3]]


@FUZZ
@given(st.data())
def test_mutated_reference_levels_convert_or_fail_in_one_line(data):
    level = data.draw(mutated(_reference_bases()))
    try:
        converted, _ = convert_reference_level(level, "ref.json")
        parse_level(converted, "ref.json").build()
    except UserError as exc:
        assert "\n" not in str(exc) and str(exc).startswith("ref.json: ")


CONFIG_BASES = [yaml.safe_load((EXPERIMENTS / name).read_text()) for name in ("cpu-small.yaml", "finetune.yaml")]


@FUZZ
@given(mutated(CONFIG_BASES))
def test_mutated_configs_load_or_fail_in_one_line(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("fuzz") / "exp.yaml"
    path.write_text(yaml.safe_dump(data, allow_unicode=True) if isinstance(data, dict) else json.dumps(data))
    try:
        load_config(path)
    except UserError as exc:
        assert "\n" not in str(exc) and str(exc).startswith(f"{path}")


@FUZZ
@given(st.binary(max_size=300))
def test_arbitrary_bytes_as_a_level_file_fail_in_one_line(tmp_path_factory, blob):
    path = tmp_path_factory.mktemp("fuzz") / "level.json"
    path.write_bytes(blob)
    with pytest.raises(UserError) as info:
        load_level(path)
    assert "\n" not in str(info.value) and str(info.value).startswith(str(path))
