"""Every float comparison in the suite states an absolute tolerance (issue 46).

A relative tolerance alone cannot hold for a value near zero in float32 (its last-bit error is absolute, ~eps times
the size of what it was computed from), and which values land near zero depends on how the CPU rounds: a blend test
passed here and failed on an AMD EPYC machine with `rtol=1e-6` alone at a value of 3e-6. So each call of
`assert_allclose` (any attribute chain ending in it, or an imported alias), chex's `assert_trees_all_close`,
`pytest.approx` and `math.isclose` in tests/ gives its absolute tolerance (`atol=`, `abs=`, `abs_tol=`: by keyword,
by position where the signature allows it, or in `**NAME` of a module-level dict that holds it), chosen from what
the value means. A bare reference (passed to `jax.tree.map`, say) counts as a call without one, unless it is
wrapped in a `partial` that gives it.

Parses the sources with `ast` and imports no jax itself: the check takes ~0.3 s of CPU.
"""

from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).resolve().parent

CHECKED = {
    "assert_allclose": ("atol", 3),  # numpy's (actual, desired, rtol, atol, ...): atol defaults to 0
    "assert_trees_all_close": ("atol", None),  # chex's (*trees, rtol, atol): atol defaults to 0
    "approx": ("abs", 2),  # pytest's (expected, rel, abs, ...): abs defaults to 1e-12
    "isclose": ("abs_tol", None),  # math's (a, b, *, rel_tol, abs_tol): abs_tol defaults to 0; numpy's is not checked
}
"""Name of a checked comparison: (keyword of its absolute tolerance, that argument's position, None if keyword-only)."""


def _chain(node: ast.expr) -> list[str] | None:
    """`a.b.c` as ["a", "b", "c"]; None for anything else (a call, a subscript)."""
    names = []
    while isinstance(node, ast.Attribute):
        names.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    return [node.id, *reversed(names)]


def _aliases(tree: ast.Module) -> dict[str, str]:
    """Local name -> checked name, for every checked comparison a module imports by name (`from math import
    isclose`, `from numpy.testing import assert_allclose as close`)."""
    aliases = {name: name for name in CHECKED if name != "isclose"}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            for alias in node.names:
                if alias.name in CHECKED and (alias.name != "isclose" or node.module == "math"):
                    aliases[alias.asname or alias.name] = alias.name
    return aliases


def _checked(func: ast.expr, aliases: dict[str, str]) -> str | None:
    """The checked comparison `func` names, if any."""
    chain = _chain(func)
    if chain is None:
        return None
    if len(chain) == 1:
        return aliases.get(chain[0])
    if chain[-1] == "isclose":
        return "isclose" if chain[:-1] == ["math"] else None  # np.isclose has a default atol
    return chain[-1] if chain[-1] in CHECKED else None


def _keyword_sets(tree: ast.Module) -> dict[str, set[str]]:
    """Module-level dicts of keywords, `NAME = {"rtol": ..., "atol": ...}` or `NAME = dict(rtol=..., atol=...)`:
    name -> the keywords `**NAME` gives."""
    sets = {}
    for node in tree.body:
        if isinstance(node, ast.Assign | ast.AnnAssign) and node.value is not None:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            value = node.value
            if isinstance(value, ast.Dict) and all(isinstance(k, ast.Constant) for k in value.keys):
                keys = {k.value for k in value.keys}
            elif isinstance(value, ast.Call) and _chain(value.func) == ["dict"] and not value.args:
                keys = {k.arg for k in value.keywords}
            else:
                continue
            sets.update((t.id, keys) for t in targets if isinstance(t, ast.Name))
    return sets


def _gives(call: ast.Call, name: str, sets: dict[str, set[str]]) -> bool:
    """Whether `call` of `name` gives its absolute tolerance (`sets`: what each module-level `**NAME` gives)."""
    keyword, position = CHECKED[name]
    for k in call.keywords:
        spread = sets.get(k.value.id, ()) if k.arg is None and isinstance(k.value, ast.Name) else ()
        if k.arg == keyword or keyword in spread:
            return True
    if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
        return False  # *args / **kwargs this cannot see into: state it by keyword
    return position is not None and len(call.args) > position


def missing(path: Path) -> list[str]:
    """`file:line name` for every checked comparison in `path` without an absolute tolerance."""
    tree = ast.parse(path.read_text(), filename=str(path))
    aliases, sets = _aliases(tree), _keyword_sets(tree)
    where = path.relative_to(TESTS.parent) if path.is_relative_to(TESTS.parent) else path
    found, judged = [], set()
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        if name := _checked(node.func, aliases):
            judged.add(id(node.func))
            if not _gives(node, name, sets):
                found.append((node.lineno, f"{where}:{node.lineno} {name}(...) has no {CHECKED[name][0]}="))
        elif (_chain(node.func) or [""])[-1] == "partial" and node.args and (name := _checked(node.args[0], aliases)):
            judged.add(id(node.args[0]))
            if not _gives(ast.Call(node.func, [], node.keywords), name, sets):
                found.append((node.lineno, f"{where}:{node.lineno} partial({name}, ...) has no {CHECKED[name][0]}="))
    for node in ast.walk(tree):  # a reference, not called here: called elsewhere with what it is given there
        loaded = isinstance(node, ast.Attribute | ast.Name) and isinstance(node.ctx, ast.Load)
        if loaded and id(node) not in judged and (name := _checked(node, aliases)):
            found.append((node.lineno, f"{where}:{node.lineno} {name} passed on without {CHECKED[name][0]}="))
    return [text for _, text in sorted(found)]


def test_every_float_comparison_states_an_absolute_tolerance():
    found = [line for path in sorted(TESTS.rglob("*.py")) for line in missing(path)]
    assert not found, "float comparisons without an absolute tolerance (issue 46):\n" + "\n".join(found)


def test_the_check_sees_what_it_must(tmp_path):
    source = tmp_path / "sample.py"
    source.write_text(
        "import math, functools\n"
        "import numpy as np\n"
        "import pytest\n"
        "from numpy.testing import assert_allclose as close\n"
        "np.testing.assert_allclose(a, b, rtol=1e-6)\n"  # 5: flagged
        "np.testing.assert_allclose(a, b, atol=1e-6)\n"
        "np.testing.assert_allclose(a, b, 1e-6, 1e-6)\n"
        "close(a, b)\n"  # 8: flagged
        "x == pytest.approx(1.0, rel=1e-6)\n"  # 9: flagged
        "x == pytest.approx(1.0, abs=1e-6)\n"
        "math.isclose(a, b, rel_tol=1e-6)\n"  # 11: flagged
        "np.isclose(a, b)\n"
        "jax.tree.map(np.testing.assert_allclose, a, b)\n"  # 13: flagged
        "jax.tree.map(functools.partial(np.testing.assert_allclose, atol=1e-6), a, b)\n"
        "np.testing.assert_allclose(a, b, **tolerance)\n"  # 15: flagged
        "chex.assert_trees_all_close(a, b, rtol=1e-5)\n"  # 16: flagged
        "CLOSE = {'rtol': 1e-5, 'atol': 1e-6}\n"
        "np.testing.assert_allclose(a, b, **CLOSE)\n"
        "RELATIVE = dict(rtol=1e-5)\n"
        "np.testing.assert_allclose(a, b, **RELATIVE)\n"  # 20: flagged
    )
    lines = [int(text.split(":")[1].split()[0]) for text in missing(source)]
    assert lines == [5, 8, 9, 11, 13, 15, 16, 20]
