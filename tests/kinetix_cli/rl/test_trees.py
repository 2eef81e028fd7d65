"""Trees compared by leaf name: the one fit check of loaded parameters and checkpoints."""

from __future__ import annotations

import jax
import numpy as np

from kinetix_cli.rl.trees import tree_mismatch


def test_a_tree_fits_itself_in_any_form_of_its_leaves():
    params = {"params": {"Dense_0": {"kernel": np.zeros((3, 4), np.float32), "bias": np.zeros(4, np.float32)}}}
    assert tree_mismatch(params, params) is None
    assert tree_mismatch(jax.eval_shape(lambda: params), params) is None  # abstract leaves (ShapeDtypeStruct)


def test_the_first_differing_leaf_is_named_with_both_shapes():
    want = {"a": np.zeros((3, 4), np.float32), "b": np.zeros(2, np.float32)}
    assert (
        tree_mismatch(want, want | {"a": np.zeros((3, 5), np.float32)})
        == "a: float32[3, 4] expected, float32[3, 5] found"
    )
    assert tree_mismatch(want, {"b": want["b"]}) == "a: float32[3, 4] expected, absent found"
    assert tree_mismatch(want, want | {"c": np.zeros(1, np.int32)}) == "c: absent expected, int32[1] found"
    assert tree_mismatch(want, want | {"b": np.zeros(2, np.float64)}) == "b: float32[2] expected, float64[2] found"
