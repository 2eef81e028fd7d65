"""Docstring examples run as tests: every code example in a docstring under src/ is a doctest, and every doctest
passes.

A docstring shows code in an `Examples:` section as `>>>` lines with their output (mkdocstrings renders the section
as Python sessions). An indented block of Python elsewhere in a docstring (Markdown shows it as code, never runs it)
fails `test_code_examples_are_doctests`, unless it is a sketch: a block with `...` placeholders for what it leaves
out. Other indented blocks (a level file's JSON, a shell command) are not Python and stay as they are.
"""

from __future__ import annotations

import ast
import doctest
import importlib
import inspect
import re
import textwrap
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parent.parent / "src"
PACKAGES = ("engine", "kinetix_cli")
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
"""`...` in an expected output matches anything (a traceback's body); runs of whitespace match any whitespace."""
SECTION = re.compile(
    r"(Args|Arguments|Attributes|Examples|Keyword Args|Methods|Other Parameters|Raises|Returns|Warns|Yields):\s*"
)
"""A Google-style section header: the indented lines under it are its items, not a code block."""


def source_files() -> list[Path]:
    return sorted(path for package in PACKAGES for path in (SRC / package).rglob("*.py"))


def module_name(path: Path) -> str:
    parts = path.relative_to(SRC).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def docstrings(path: Path) -> dict[str, str]:
    """Every docstring of a source file by the name doctest gives it (`module.Class.method`): the module's,
    its classes' and functions' (nested ones too), and the attribute docstrings under assignments."""
    found: dict[str, str] = {}

    def visit(node: ast.AST, name: str) -> None:
        doc = ast.get_docstring(node, clean=False) if not isinstance(node, ast.Expr) else node.value.value
        if doc:
            found[name] = doc
        body = getattr(node, "body", [])
        for previous, child in zip([None, *body], body, strict=False):
            if isinstance(child, ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
                visit(child, f"{name}.{child.name}")
            elif (
                isinstance(previous, ast.Assign | ast.AnnAssign)
                and isinstance(child, ast.Expr)
                and isinstance(child.value, ast.Constant)
                and isinstance(child.value.value, str)
            ):
                targets = previous.targets if isinstance(previous, ast.Assign) else [previous.target]
                label = ",".join(ast.unparse(target) for target in targets)
                visit(child, f"{name}.{label}")

    visit(ast.parse(path.read_text()), module_name(path))
    return found


def literal_blocks(doc: str) -> list[str]:
    """The indented blocks Markdown shows as code: lines indented 4 or more after a blank line (or after a line
    ending in reStructuredText's `::`) under an unindented paragraph that is not a section header."""
    lines = inspect.cleandoc(doc).splitlines()
    blocks, i = [], 0
    while i < len(lines):
        previous = next((line for line in reversed(lines[:i]) if line.strip()), None)
        opens = (
            lines[i].startswith("    ")
            and lines[i].strip()
            and previous is not None
            and not previous.startswith(" ")
            and not SECTION.fullmatch(previous)
            and (not lines[i - 1].strip() or previous.endswith("::"))
        )
        if not opens:
            i += 1
            continue
        end = i
        while end < len(lines) and (lines[end].startswith("    ") or not lines[end].strip()):
            end += 1
        blocks.append(textwrap.dedent("\n".join(lines[i:end])).strip())
        i = end
    return blocks


def is_python_example(block: str) -> bool:
    """Whether an indented block is Python that runs: it parses, does something (a call, an import, an
    assignment), and has no `...` placeholder (which makes it a sketch)."""
    if block.startswith(">>>"):
        return False
    try:
        tree = ast.parse(block)
    except SyntaxError:
        return False
    nodes = list(ast.walk(tree))
    if any(isinstance(node, ast.Constant) and node.value is Ellipsis for node in nodes):
        return False
    return any(isinstance(node, ast.Call | ast.Import | ast.ImportFrom | ast.Assign) for node in nodes)


def collect_doctests() -> list[doctest.DocTest]:
    """The doctests of every module whose source holds `>>>`, as doctest finds them."""
    finder = doctest.DocTestFinder()
    tests = []
    for path in source_files():
        if ">>>" in path.read_text():
            tests += [test for test in finder.find(importlib.import_module(module_name(path))) if test.examples]
    return sorted(tests, key=lambda test: test.name)


DOCTESTS = collect_doctests()


def test_docstring_examples_exist_and_doctest_collects_them():
    """Every docstring holding `>>>` is one doctest runs (not, say, an attribute docstring, which it skips)."""
    with_examples = {name for path in source_files() for name, doc in docstrings(path).items() if ">>>" in doc}
    assert with_examples, "no docstring under src/ has a doctest"
    assert with_examples == {test.name for test in DOCTESTS}


@pytest.mark.parametrize("test", DOCTESTS, ids=[test.name for test in DOCTESTS])
def test_doctest_passes(test: doctest.DocTest):
    report: list[str] = []
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    result = runner.run(test, out=report.append)
    if result.failed:
        pytest.fail("".join(report), pytrace=False)


def test_code_examples_are_doctests():
    untested = [
        f"{name}:\n{textwrap.indent(block, '    ')}"
        for path in source_files()
        for name, doc in docstrings(path).items()
        for block in literal_blocks(doc)
        if is_python_example(block)
    ]
    assert not untested, "Python in a docstring that never runs; write it as an `Examples:` doctest:\n" + "\n".join(
        untested
    )


@pytest.mark.parametrize(
    ("paragraph", "found"),
    [
        ("Use it so::\n\n    x = f(1)\n", True),  # reStructuredText's literal block
        ("Use it so:\n\n    import gymnasium\n    env = gymnasium.make('x')\n", True),  # Markdown's code block
        ("Use it so:\n\n    >>> f(1)\n    2\n", False),  # a doctest
        ("Examples:\n    >>> f(1)\n    2\n", False),
        ("Args:\n    level: Level\n    static: sizes(x)\n", False),  # a section's items
        ("Loop:\n\n    for u in updates:\n        runner = update(runner, ...)\n", False),  # a sketch
        ('A file holds:\n\n    "solution": {"actions": [[[1, 0, 0, 0, 0, 0], 40]]}\n', False),  # JSON
        ("Run:\n\n    kinetix eval general --levels s\n", False),  # a shell command
        ("A paragraph, then\n    x = f(1)\n", False),  # no blank line before it: not a block
    ],
)
def test_what_counts_as_an_untested_code_example(paragraph: str, found: bool):
    doc = f"Summary line.\n\n{paragraph}"  # as in a docstring: the summary, then the paragraph under test
    assert any(is_python_example(block) for block in literal_blocks(doc)) == found
