"""MkDocs hook of the documentation site: the repository's README, BENCHMARKS.md, CHANGELOG.md and levels/README.md
become pages (index.md, benchmarks.md, changelog.md, levels.md), with their links rewritten for the site: a guide in
docs/ by its page, those four by theirs, and a repository file the site does not carry (source, scripts, the
experiments' raw evidence that mkdocs.yml's exclude_docs keeps out) as its path in code type."""

from __future__ import annotations

import posixpath
import re
from pathlib import Path

from mkdocs.structure.files import File, Files

ROOT = Path(__file__).resolve().parent.parent
PAGES = {
    "README.md": "index.md",
    "BENCHMARKS.md": "benchmarks.md",
    "CHANGELOG.md": "changelog.md",
    "levels/README.md": "levels.md",
}
LINK = re.compile(r"(!?)\[([^\]]*)\]\(([^)\s]+)\)")


def on_files(files: Files, config) -> Files:
    for source, page in PAGES.items():
        text = _rewrite((ROOT / source).read_text(encoding="utf-8"), Path(source).parent, page, files)
        files.append(File.generated(config, page, content=text))
    return files


def on_page_markdown(markdown, page, config, files):
    """The guides' links to repository files outside docs/ (../BENCHMARKS.md, ...), and the experiments' links to
    their raw files."""
    if page.file.src_uri in PAGES.values():
        return markdown
    return _rewrite(markdown, Path("docs") / Path(page.file.src_uri).parent, page.file.src_uri, files)


def _in_site(files: Files, uri: str) -> bool:
    """Whether the site carries the docs/ file `uri` (a file exclude_docs leaves out is not carried)."""
    file = files.get_file_from_path(uri)
    return file is not None and file.inclusion.is_included()


def _rewrite(text: str, folder: Path, page: str, files: Files) -> str:
    """`text`'s relative links, written in `folder` of the repository, as links from the site page `page`."""

    def link(match: re.Match) -> str:
        bang, label, target = match.groups()
        if re.match(r"^[a-z]+:|^#", target):
            return match.group(0)
        path, _, anchor = target.partition("#")
        resolved = (ROOT / folder / path).resolve()
        relative = resolved.relative_to(ROOT).as_posix() if resolved.is_relative_to(ROOT) else path
        if relative in PAGES:
            uri = PAGES[relative]
        elif relative.startswith("docs/") and _in_site(files, relative.removeprefix("docs/")):
            uri = relative.removeprefix("docs/")
        else:
            return f"{label} (`{relative}`)"
        href = posixpath.relpath(uri, posixpath.dirname(page) or ".")
        return f"{bang}[{label}]({href}{'#' + anchor if anchor else ''})"

    return LINK.sub(link, text)
