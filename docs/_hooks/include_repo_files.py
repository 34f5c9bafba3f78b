"""MkDocs hook: show a Markdown file of the repository that lives outside ``docs/`` on a page.

A page marks the place with a block whose first line names the file (each marker alone on
its line)::

    <!-- include: RESULTS.md -->
    On GitHub this text is shown; on the site the file's content replaces the whole block.
    <!-- end include -->

On the site the block becomes the file's text, with every relative link and image target
rewritten to work from the page: targets inside ``docs/`` point to the built pages and
pictures, targets elsewhere in the repository become their path in code (the site holds only
``docs/``). A missing file is an error, so ``mkdocs build --strict`` fails instead of showing
an empty page.
"""

from __future__ import annotations

import posixpath
import re
from pathlib import Path

from mkdocs.exceptions import PluginError

_BLOCK = re.compile(r"^<!-- include: (?P<path>\S+) -->\n.*?^<!-- end include -->$", re.DOTALL | re.MULTILINE)
_LINK = re.compile(r"(?P<bang>!?)\[(?P<text>[^\]]*)\]\((?P<target>[^)\s]+)\)")
_FENCE = re.compile(r"^(```|~~~)")


def _rewrite_links(text: str, source: str, page: str, docs_dir: str) -> str:
    """Rewrite the relative link targets of ``text`` (written at repository path ``source``)
    for the page at docs path ``page``; code fences are left alone."""
    source_dir = posixpath.dirname(source)
    page_dir = posixpath.dirname(page)

    def fix(match: re.Match) -> str:
        target = match["target"]
        if re.match(r"^[a-z][a-z0-9+.-]*:|^#|^/", target):  # absolute URL, anchor, site root
            return match[0]
        path, _, anchor = target.partition("#")
        in_repo = posixpath.normpath(posixpath.join(source_dir, path))
        if in_repo.startswith(docs_dir + "/"):
            new = posixpath.relpath(in_repo[len(docs_dir) + 1:], page_dir or ".")
            return f"{match['bang']}[{match['text']}]({new}{'#' + anchor if anchor else ''})"
        return f"{match['text']} (`{in_repo}`)" if match["text"] else f"`{in_repo}`"

    out, fenced = [], False
    for line in text.splitlines(keepends=True):
        if _FENCE.match(line.lstrip()):
            fenced = not fenced
        out.append(line if fenced else _LINK.sub(fix, line))
    return "".join(out)


def on_page_markdown(markdown: str, page, config, files) -> str:
    """Replace every include block of the page by the named file's rewritten text."""
    docs_dir = Path(config["docs_dir"]).resolve()
    root = docs_dir.parent

    def include(match: re.Match) -> str:
        path = match["path"]
        source = (root / path).resolve()
        if not source.is_file() or root not in source.parents:
            raise PluginError(f"{page.file.src_uri}: '<!-- include: {path} -->' names no file of the repository")
        return _rewrite_links(source.read_text(encoding="utf-8"), path, page.file.src_uri, docs_dir.name)

    return _BLOCK.sub(include, markdown)
