"""MkDocs hook: figure descriptions and folded cells on the notebook pages, from comments in the notebook source.

Two conventions, written as comment lines in a code cell of a jupytext notebook (``notebooks/*.py``):

``# alt: TEXT``
    The description (``alt`` text) of the figure the cell draws: what the figure shows, for a reader who
    cannot see it. One ``# alt:`` line per figure, in the order the cell outputs them; a description may
    go on over the following comment lines if they are indented (``#     more text``). nbconvert gives an
    image without one the text "No description has been provided for this image", which the browser
    check (``scripts/browser_check.py``) refuses.

``# fold: SUMMARY``
    Show the cell's code folded: a ``<details>`` element whose ``<summary>`` is SUMMARY (for example
    "Setup: imports and helper functions"); its outputs stay visible. For long setup cells, so that a page
    reads as an argument with its results, not as an executed log.

The hook runs on the HTML that mkdocs-jupyter (nbconvert's lab template) renders: each code cell is a
``div.jp-CodeCell`` with its source in the ``pre`` of its input area and its outputs in
``div.jp-Cell-outputWrapper``. A cell with more ``# alt:`` lines than images is a build warning (an error
under ``mkdocs build --strict``): the description would land on the wrong figure.
"""

from __future__ import annotations

import logging
import re
from typing import Any

from bs4 import BeautifulSoup, Tag

log = logging.getLogger("mkdocs.hooks.notebook_pages")

NO_ALT = "No description has been provided for this image"
ALT_RE = re.compile(r"^[ \t]*# alt:[ \t]*(.+?)[ \t]*$((?:\n[ \t]*#[ \t]{2,}\S.*$)*)", re.M)
FOLD_RE = re.compile(r"^[ \t]*# fold:[ \t]*(.+?)[ \t]*$", re.M)


def descriptions(source: str) -> list[str]:
    """The ``# alt:`` descriptions of a cell's source, in order, continuation lines joined."""
    out = []
    for m in ALT_RE.finditer(source):
        more = [line.strip().lstrip("#").strip() for line in m.group(2).splitlines() if line.strip()]
        out.append(" ".join([m.group(1), *more]))
    return out


def fold_summary(source: str) -> str | None:
    """The ``# fold:`` summary of a cell's source, or None."""
    m = FOLD_RE.search(source)
    return m.group(1) if m else None


def _is_notebook(page: Any) -> bool:
    return page.file.src_uri.endswith((".py", ".ipynb"))


def _code_cells(soup: BeautifulSoup) -> list[Tag]:
    """The code cells (mkdocs-jupyter wraps each in a second div of the same classes: the inner one, with
    an id, is the cell)."""
    return [c for c in soup.select("div.jp-CodeCell") if not c.select_one("div.jp-CodeCell")]


def on_page_content(html: str, page: Any, config: Any, files: Any) -> str:
    if not _is_notebook(page) or "jp-CodeCell" not in html:
        return html
    soup = BeautifulSoup(html, "html.parser")
    changed = False
    for n, cell in enumerate(_code_cells(soup), start=1):
        pre = cell.select_one("div.jp-InputArea pre")
        source = pre.get_text() if pre is not None else ""
        alts = descriptions(source)
        images = cell.select("div.jp-Cell-outputWrapper img")
        if len(alts) > len(images):
            log.warning(
                "notebook_pages: %s, code cell %d: %d '# alt:' line(s) for %d image(s)",
                page.file.src_uri, n, len(alts), len(images),
            )  # fmt: skip
        for img, alt in zip(images, alts, strict=False):
            img["alt"] = alt
            changed = True
        summary = fold_summary(source)
        wrapper = cell.select_one("div.jp-Cell-inputWrapper")
        if summary and wrapper is not None:
            details = soup.new_tag("details", attrs={"class": "nb-fold"})
            label = soup.new_tag("summary")
            label.string = summary
            wrapper.wrap(details)
            details.insert(0, label)
            changed = True
    return str(soup) if changed else html
