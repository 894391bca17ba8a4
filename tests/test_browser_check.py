"""scripts/browser_check.py's reader checks on a small page that breaks each rule once: a raw Sphinx role, an
image with nbconvert's placeholder description, a box that hides its overflow, a table past the column; and
a wide line in a scroll box, which is allowed. Needs Debian's chromium and playwright (as make test does)."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
pytest.importorskip("playwright.sync_api")
if not Path(CHROMIUM).exists():
    pytest.skip("needs chromium", allow_module_level=True)

PIXEL = (
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg=="
)
LONG = "a line of code much longer than the three hundred pixels of the box that holds it, by far"


def _page(body: str) -> str:
    return (
        '<html><body><div class="md-content" style="width:600px"><div class="md-content__inner">'
        f"{body}</div></div></body></html>"
    )


def _check(tmp_path: Path, body: str):
    sys.path.insert(0, str(ROOT / "scripts"))
    try:
        import browser_check as bc
    finally:
        sys.path.pop(0)
    from playwright.sync_api import sync_playwright

    (tmp_path / "index.html").write_text(_page(body))
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=bc.CHROMIUM_ARGS, headless=True)
        try:
            context = browser.new_context(viewport={"width": bc.WIDTHS[0], "height": 900})
            return bc.check_page(context, tmp_path.as_uri() + "/", "index.html", tmp_path, from_disk=True)
        finally:
            browser.close()


def test_a_clean_page_passes_and_a_scroll_box_may_hold_a_wide_line(tmp_path):
    body = f'<p>text</p><img src="{PIXEL}" alt="one grey pixel"><div style="overflow-x:auto;width:300px"><pre>{LONG}</pre></div>'
    result = _check(tmp_path, body)
    assert result.problems == []


def test_each_rule_fails_its_page(tmp_path):
    body = (
        "<p>see :func:`~motionsig_cli.x`</p>"
        f'<img src="{PIXEL}" alt="No description has been provided for this image">'
        f'<div style="overflow:hidden;width:300px"><pre>{LONG}</pre></div>'
        '<table style="width:900px"><tr><td>a table wider than the column</td></tr></table>'
    )
    problems = " | ".join(_check(tmp_path, body).problems)
    assert "1 raw Sphinx role" in problems
    assert "1 image(s) without a description" in problems
    for width in (1400, 900):
        assert f"at {width} px" in problems and "hides" in problems and "past the column" in problems
