"""MkDocs hook of the documentation site: the repository's README, BENCHMARKS.md and levels/README.md become
pages (index.md, benchmarks.md, levels.md), with their links rewritten for the site: a guide in docs/ by its page,
those three by theirs, and a repository file the site does not carry as its path in code type."""

from __future__ import annotations

import re
from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parent.parent
PAGES = {"README.md": "index.md", "BENCHMARKS.md": "benchmarks.md", "levels/README.md": "levels.md"}
LINK = re.compile(r"(!?)\[([^\]]*)\]\(([^)\s]+)\)")


def on_files(files, config):
    for source, page in PAGES.items():
        text = _rewrite((ROOT / source).read_text(encoding="utf-8"), Path(source).parent, config)
        files.append(File.generated(config, page, content=text))
    return files


def on_page_markdown(markdown, page, config, files):
    """The guides' links to repository files outside docs/ (../BENCHMARKS.md, ...)."""
    if page.file.src_uri in PAGES.values():
        return markdown
    return _rewrite(markdown, Path("docs") / Path(page.file.src_uri).parent, config)


def _rewrite(text: str, folder: Path, config) -> str:
    docs = Path(config["docs_dir"])

    def link(match: re.Match) -> str:
        bang, label, target = match.groups()
        if re.match(r"^[a-z]+:|^#", target):
            return match.group(0)
        path, _, anchor = target.partition("#")
        resolved = (ROOT / folder / path).resolve()
        relative = resolved.relative_to(ROOT).as_posix() if resolved.is_relative_to(ROOT) else path
        if relative in PAGES:
            return f"{bang}[{label}]({PAGES[relative]}{'#' + anchor if anchor else ''})"
        if relative.startswith("docs/") and (docs / relative.removeprefix("docs/")).exists():
            return f"{bang}[{label}]({relative.removeprefix('docs/')}{'#' + anchor if anchor else ''})"
        return f"{label} (`{relative}`)"

    return LINK.sub(link, text)
