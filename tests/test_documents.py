"""README and BENCHMARKS.md agree on every headline number.

Each row of README's "What it achieves" table links to one or more sections of BENCHMARKS.md. Every number in the
row's result must appear, as written or more precisely, in BENCHMARKS.md's Summary row of a section the README row
links to; for a linked section without a Summary row (a subsection), in the section's text. README may round (50%
for 50.4%, 316K for 316,412), never state a number its BENCHMARKS.md row does not hold. A range (7.2-18.4x) is its
two ends. Version numbers (Jax2D 1.0.2), dates and numbers inside names (H100, v3, 2D) are not headline numbers.

The Summary row, not its whole section, because a section holds hundreds of numbers: a changed README number would
too often equal one of them by chance.
"""

from __future__ import annotations

import re
from decimal import Decimal
from pathlib import Path
from typing import NamedTuple

import pytest

ROOT = Path(__file__).resolve().parent.parent
README_TABLE = "What it achieves"
SUMMARY_TABLE = "Summary"

_LINK = re.compile(r"\[([^\]]*)\]\(([^)\s]*)\)")
_DATE = re.compile(r"\b\d{4}-\d{2}-\d{2}\b")
_NUMBER = re.compile(r"(?<![\w.])(\d{1,3}(?:,\d{3})+|\d+)(\.\d+)?([KM%x]?)(?!\w|\.\d)")
_SCALE = {"K": Decimal(1000), "M": Decimal(1_000_000)}
_HEADING = re.compile(r"(#{1,6})\s+(.*?)\s*#*\s*")


class Number(NamedTuple):
    """A number as a document writes it, its value and the step of its last digit (22.0% has step 0.1, 316K 1000)."""

    text: str
    value: Decimal
    step: Decimal


def numbers(text: str) -> list[Number]:
    """The numbers of a piece of Markdown: link targets, dates and versions left out; "1,024" is 1024, "5.9K" 5900."""
    text = _DATE.sub(" ", _LINK.sub(r"\1", text))
    found = []
    for match in _NUMBER.finditer(text):
        whole, fraction, unit = match.group(1), match.group(2) or "", match.group(3)
        scale = _SCALE.get(unit, Decimal(1))
        value = Decimal(whole.replace(",", "") + fraction) * scale
        step = Decimal(1).scaleb(1 - len(fraction) if fraction else 0) * scale
        found.append(Number(match.group(0), value, step))
    return found


def states(source: Number, claim: Number) -> bool:
    """Whether `source` states `claim`: as precisely or more, and equal once rounded to the claim's last digit."""
    return source.step <= claim.step and abs(source.value - claim.value) * 2 <= claim.step


def slug(heading: str) -> str:
    """GitHub's anchor of a Markdown heading: lower case, punctuation dropped, spaces as hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def sections(markdown: str) -> dict[str, str]:
    """Each heading's anchor -> its text up to the next heading of the same or a higher level (subsections in)."""
    headings = []  # (line index, level, anchor)
    lines = markdown.splitlines()
    fenced = False
    for i, line in enumerate(lines):
        fenced ^= line.startswith("```")
        match = None if fenced else _HEADING.fullmatch(line)
        if match:
            headings.append((i, len(match.group(1)), slug(match.group(2))))
    found = {}
    for k, (start, level, anchor) in enumerate(headings):
        end = next((i for i, lev, _ in headings[k + 1 :] if lev <= level), len(lines))
        found.setdefault(anchor, "\n".join(lines[start + 1 : end]))
    return found


def table_rows(section: str) -> list[list[str]]:
    """The cells of each body row of the first table in a section (header and separator rows left out)."""
    rows: list[list[str]] = []
    for line in section.splitlines():
        if not line.startswith("|"):
            if rows:
                break
            continue
        rows.append([cell.strip() for cell in re.split(r"(?<!\\)\|", line.strip().strip("|"))])
    return rows[2:]


def linked_anchors(cells: list[str], document: str) -> list[str]:
    """The anchors of the links to `document` (a file name, or "" for the same document) in a table row."""
    anchors = []
    for _, target in (match.groups() for cell in cells for match in _LINK.finditer(cell)):
        path, _, anchor = target.partition("#")
        if path == document and anchor and anchor not in anchors:
            anchors.append(anchor)
    return anchors


def headline_disagreements(readme: str, benchmarks: str) -> list[str]:
    """One line per number of README's "What it achieves" table that BENCHMARKS.md does not hold where the row
    links (a Summary row, or the text of a section without one), and per link to a section BENCHMARKS.md does not
    have."""
    readme_rows = table_rows(sections(readme).get(slug(README_TABLE), ""))
    if not readme_rows:
        return [f'README.md: no "{README_TABLE}" table']
    topics = sections(benchmarks)
    summary = {}
    for row in table_rows(topics.get(slug(SUMMARY_TABLE), "")):
        for anchor in linked_anchors(row[:1], ""):
            summary[anchor] = " ".join(row[1:])
    problems = []
    for row in readme_rows:
        name = _LINK.sub(r"\1", row[0])
        anchors = linked_anchors(row, "BENCHMARKS.md")
        if not anchors:
            problems.append(f"README row {name!r}: links no section of BENCHMARKS.md")
            continue
        for anchor in anchors:
            if anchor not in topics:
                problems.append(f"README row {name!r}: BENCHMARKS.md has no section #{anchor}")
        held = {a: summary[a] if a in summary else topics.get(a, "") for a in anchors}
        sources = [number for text in held.values() for number in numbers(text)]
        where = " or ".join(f"{'Summary row' if a in summary else 'section'} #{a}" for a in anchors)
        claims = {claim.text: claim for cell in row[1:] for claim in numbers(cell)}
        for claim in claims.values():
            if not any(states(source, claim) for source in sources):
                problems.append(f"README row {name!r}: {claim.text} is not in BENCHMARKS.md's {where}")
    return problems


def read(name: str) -> str:
    return (ROOT / name).read_text(encoding="utf-8")


def test_readme_headlines_agree_with_benchmarks():
    problems = headline_disagreements(read("README.md"), read("BENCHMARKS.md"))
    assert not problems, "README.md and BENCHMARKS.md disagree:\n" + "\n".join(problems)


def test_a_planted_disagreement_is_the_one_reported():
    readme, benchmarks = read("README.md"), read("BENCHMARKS.md")
    assert readme.count("117,523") == 1, "the planted number must be README's environment headline, once"
    today = headline_disagreements(readme, benchmarks)
    planted = headline_disagreements(readme.replace("117,523", "117,524"), benchmarks)
    assert [line for line in planted if line not in today] == [
        "README row 'Environment': 117,524 is not in BENCHMARKS.md's Summary row #environment"
    ]
    assert set(today) <= set(planted)


BENCHMARKS = """# Benchmarks

## Summary

| topic | current headline |
| --- | --- |
| [Engine](#engine) | 7.2x-18.4x Jax2D at 64 and 1024 envs |
| [Agents](#agents) | general 22.0 / 22.1%, general-s v2 50.4 / 48.4% (seeds 0-2) |

## Engine

```bash
# a comment, not a heading
```

### Engine on a GPU

2.2-2.3x at 1,024 scenes on an H100

## Agents

48.5% on another suite.
"""


@pytest.mark.parametrize(
    ("row", "problems"),
    [
        ("| [Engine](BENCHMARKS.md#engine) | 7.2-18.4x Jax2D 1.0.2 at 64 and 1,024 scenes |", []),
        ("| [Agents](BENCHMARKS.md#agents) | `general` v3 22.0%, general-s v2 50% (seeds 0-2) |", []),
        (
            "| [Agents](BENCHMARKS.md#agents) | 22.1% and 48.5% |",  # 48.5% is in the section, not the Summary row
            ["README row 'Agents': 48.5% is not in BENCHMARKS.md's Summary row #agents"],
        ),
        (
            "| [Agents](BENCHMARKS.md#agents) | 22.10% |",  # more precise than BENCHMARKS.md says
            ["README row 'Agents': 22.10% is not in BENCHMARKS.md's Summary row #agents"],
        ),
        ("| [Engine](BENCHMARKS.md#engine) | 7.2x; 2.3x ([GPU](BENCHMARKS.md#engine-on-a-gpu)) |", []),
        (
            "| [Engine](BENCHMARKS.md#engine) | 7.2x; 2.3x on a GPU |",
            ["README row 'Engine': 2.3x is not in BENCHMARKS.md's Summary row #engine"],
        ),
        (
            "| [GPU](BENCHMARKS.md#gpu) | 3x |",
            [
                "README row 'GPU': BENCHMARKS.md has no section #gpu",
                "README row 'GPU': 3x is not in BENCHMARKS.md's section #gpu",
            ],
        ),
        ("| Engine | 7.2x |", ["README row 'Engine': links no section of BENCHMARKS.md"]),
    ],
)
def test_checker_on_small_documents(row: str, problems: list[str]):
    readme = f"# kinetix\n\n## {README_TABLE}\n\n| what | result |\n| --- | --- |\n{row}\n\n## Install\n"
    assert headline_disagreements(readme, BENCHMARKS) == problems


@pytest.mark.parametrize(
    ("text", "values"),
    [
        ("117,523 env steps/s", ["117523"]),
        ("1024 and 1,024", ["1024", "1024"]),
        ("7.2-18.4x and 7.2x-18.4x", ["7.2", "18.4", "7.2", "18.4"]),
        ("22.0% of 74 levels", ["22.0", "74"]),
        ("316K env steps/s, 5.9K, 9.25M", ["316000", "5900", "9250000"]),
        ("0 / 0 / 0% (seeds 0-2)", ["0", "0", "0", "0", "2"]),
        ("Jax2D 1.0.2 on an H100, general v3, 2D, 2026-11-22, [GPU](BENCHMARKS.md#gpu-2)", []),
    ],
)
def test_numbers(text: str, values: list[str]):
    assert [number.value for number in numbers(text)] == [Decimal(value) for value in values]


@pytest.mark.parametrize(
    ("source", "claim", "agree"),
    [
        ("117,523", "117,523", True),
        ("117,523", "117,524", False),
        ("1024", "1,024", True),
        ("50.4%", "50%", True),  # README may round
        ("22%", "22.0%", False),  # but not claim a digit BENCHMARKS.md does not give
        ("316,412", "316K", True),
        ("316K", "316K", True),
        ("317,000", "316K", False),
        ("5.9K", "5,900", False),  # 5.9K says nothing of the units digit
        ("18.4x", "18x", True),
    ],
)
def test_a_number_states_a_claim(source: str, claim: str, agree: bool):
    (source_number,), (claim_number,) = numbers(source), numbers(claim)
    assert states(source_number, claim_number) == agree
