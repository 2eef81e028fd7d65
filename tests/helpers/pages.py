"""Checks of a `kinetix report` folder: the page parses with every element closed in order, every file it
references is in the folder (nothing remote, nothing outside), and report.json is of the report format."""

from __future__ import annotations

import collections
from html.parser import HTMLParser
from pathlib import Path

from kinetix_cli.constants import REPORT_FORMAT
from kinetix_cli.io import read_format

VOID = {"meta", "img", "br", "hr", "link", "input", "source"}


class Page(HTMLParser):
    """A strict reading of a page: tag counts, referenced files (src, href), and an error for an element closed
    out of order or left open."""

    def __init__(self) -> None:
        super().__init__()
        self.open: list[str] = []
        self.tags: collections.Counter = collections.Counter()
        self.refs: list[str] = []
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs) -> None:
        self.tags[tag] += 1
        self.refs += [value for name, value in attrs if name in ("src", "href")]
        if tag not in VOID:
            self.open.append(tag)

    def handle_endtag(self, tag) -> None:
        assert self.open and self.open[-1] == tag, f"</{tag}> closes {self.open[-1:]}"
        self.open.pop()

    def handle_data(self, data) -> None:
        self.text.append(data)


def read_report(folder: Path) -> tuple[Page, dict]:
    """The parsed page and report.json of a report folder, after checking both."""
    page = Page()
    page.feed((folder / "index.html").read_text(encoding="utf-8"))
    page.close()
    assert page.open == [], f"left open: {page.open}"
    assert page.tags["html"] == page.tags["body"] == 1
    for ref in page.refs:
        assert "://" not in ref and not ref.startswith("/") and ".." not in ref, ref
        assert (folder / ref).is_file(), f"the page references {ref}, which is not in {folder}"
    return page, read_format(folder / "report.json", REPORT_FORMAT)
