"""Trees of arrays compared by leaf name: the one check that parameters or a saved training state fit the tree a
config makes, used wherever parameters are loaded (agents, checkpoints, fine-tuning)."""

from __future__ import annotations

import jax
import numpy as np


def leaf_name(path) -> str:
    """A tree path as "params/params/Dense_0/kernel" (dataclass fields, dict keys and indices alike)."""
    return "/".join(str(getattr(k, "name", getattr(k, "key", getattr(k, "idx", k)))) for k in path)


def leaf_specs(tree) -> dict[str, tuple[tuple[int, ...], np.dtype]]:
    """(shape, dtype) of every leaf by name; the leaves are arrays or anything with a shape and dtype (a
    `jax.ShapeDtypeStruct`, orbax's array metadata)."""
    leaves = jax.tree_util.tree_flatten_with_path(tree)[0]
    return {leaf_name(p): _spec(x if hasattr(x, "shape") else np.asarray(x)) for p, x in leaves}


def _spec(x) -> tuple[tuple[int, ...], np.dtype]:
    return tuple(x.shape), np.dtype(x.dtype)


def tree_mismatch(expected, actual) -> str | None:
    """The first leaf (by name) that is missing, extra, or of another shape or dtype in `actual` than in
    `expected`, as "name: float32[64, 3] expected, float32[32, 3] found"; None when the trees fit."""
    want, have = leaf_specs(expected), leaf_specs(actual)
    for name in sorted(set(want) | set(have)):
        if want.get(name) != have.get(name):
            return f"{name}: {_describe(want.get(name))} expected, {_describe(have.get(name))} found"
    return None


def _describe(spec) -> str:
    return "absent" if spec is None else f"{spec[1]}{list(spec[0])}"
