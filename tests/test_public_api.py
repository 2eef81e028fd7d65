"""Code outside `src/` (tests, examples, benchmarks, docs, the experiments' raw scripts) uses the public API only:
no `from kinetix_cli... import _private` nor `from engine... import _private`. What a script needs becomes a
command or a documented function instead."""

from __future__ import annotations

import ast
from pathlib import Path

from helpers.paths import REPO

PACKAGES = ("kinetix_cli", "engine")
SKIPPED = {"src", ".venv", ".cache", ".git", "demo-out", "runs"}


def private_imports(path: Path) -> list[str]:
    """`file:line module: names` for every private name a file imports from the project's packages."""
    where = path.relative_to(REPO) if path.is_relative_to(REPO) else path
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] in PACKAGES:
            parts = node.module.split(".") + [alias.name for alias in node.names]
            if any(part.startswith("_") and part != "__init__" for part in parts):
                found.append(f"{where}:{node.lineno} {node.module}: {[a.name for a in node.names]}")
        elif isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                if parts[0] in PACKAGES and any(part.startswith("_") for part in parts):
                    found.append(f"{where}:{node.lineno} {alias.name}")
    return found


def test_nothing_outside_src_imports_a_private_name():
    files = [p for p in REPO.rglob("*.py") if not SKIPPED & set(p.relative_to(REPO).parts)]
    assert len(files) > 50
    assert [hit for path in files for hit in private_imports(path)] == []


def test_the_check_sees_a_private_import(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text("from kinetix_cli.rl.agents import _write_agent, load_policy\nimport engine._x\n")
    assert len(private_imports(sample)) == 2
