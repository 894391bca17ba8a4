"""Load every page of the built docs site in headless chromium and check that it works offline.

    python scripts/browser_check.py site

The site is served on 127.0.0.1 (a free port, http.server in a thread) and every HTML page is
opened with the Debian ``chromium`` through playwright (no browser is ever downloaded). A page
fails on

* a failed request (network error, or HTTP status >= 400);
* any request to a host other than 127.0.0.1 (such requests are aborted, so nothing leaves the
  machine, and counted as failures);
* a console error or an uncaught exception;
* an ``<img>`` that did not load (``complete && naturalWidth > 0`` after the load event);
* math that MathJax did not typeset: every page waits for ``MathJax.startup.promise``; a page with
  math (arithmatex elements, or the notebook page) must contain ``mjx-container`` elements with
  SVG inside; on any page a TeX error or an undefined macro, or an SVG glyph reference without
  its definition, fails.

What a reader sees is checked too, at a window of 1400 px and again at 900 px (the page resized in place):

* no raw Sphinx role in the text (``:func:`x```, ``:mod:~x``: docs/hooks/sphinx_roles.py renders them);
* every image of the content has a description: an ``alt`` that is present, not empty and not nbconvert's
  "No description has been provided for this image" (docs/hooks/notebook_pages.py, ``# alt:`` comments);
* nothing in the main column is cut off on the right: no element of the content reaches past the column
  unless a scroll box (``overflow-x: auto``) holds it, and no box that hides its overflow (``hidden``,
  ``clip``) has content wider than itself; the page itself does not scroll sideways.

The notebook page (URL containing ``signatures``) is also saved as a full-page screenshot to
``SITE_DIR/_check/signatures.png``. Finally the check follows one link with material's instant
navigation (home -> notebook page) and requires the new page's math to be typeset too, when the
site enables it (material's ``navigation.instant``, which works only with a matching ``site_url``).

Then every page is opened a second time **from disk** (``file://``), as a reader who opens
``site/index.html`` without a server would. There a page also fails on a link to another page of the
site that does not resolve to a file (a link to a directory shows a listing, not the page). The search
box cannot work from disk (the browser refuses the search worker's requests on ``file://``); the one
error that this raises is expected there; the search page and the 404 page (which a server sends for
any missing path, so its links are root-relative) are not checked from disk.

One line per page (OK/FAIL with reasons), then ``browser check: N passed, M failed``; the exit
status is 1 on any failure, 2 on a usage or setup error.
"""

from __future__ import annotations

import argparse
import functools
import http.server
import json
import os
import re
import shutil
import sys
import threading
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import unquote, urlsplit

PAGE_TIMEOUT_MS = 30_000
HOST = "127.0.0.1"
SCREENSHOT_PAGES = ("signatures",)
MATH_PAGES = ("signatures",)  # pages that must contain typeset math whatever their markup
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]

# Wait for MathJax (if the page loads it) to finish typesetting; resolves to a status string.
JS_WAIT_MATHJAX = """
async () => {
  const deadline = Date.now() + %d;
  while (Date.now() < deadline) {
    const mj = window.MathJax;
    if (mj && mj.startup && mj.startup.promise && mj.typesetPromise) {
      let p;
      do { p = mj.startup.promise; await p; } while (p !== mj.startup.promise);
      return "typeset";
    }
    if (document.readyState === "complete" && !document.querySelector("script[src*='mathjax']")) {
      return "no-mathjax";
    }
    await new Promise((r) => setTimeout(r, 50));
  }
  return "timeout";
}
"""

# Typeset math on the page. An error is a formula with a TeX error (merror) or an undefined macro
# (MathJax's noundefined extension writes it as red text).
JS_MATH_STATE = """
() => {
  const containers = Array.from(document.querySelectorAll("mjx-container"));
  const sources = new Map();
  try {
    for (const item of window.MathJax.startup.document.math) sources.set(item.typesetRoot, item.math);
  } catch (e) { /* no MathJax, or internals changed: report without the TeX source */ }
  const errors = [];
  for (const c of containers) {
    const bad = c.querySelector(
      "[data-mml-node='merror'], mjx-merror, [data-mml-node='mtext'][fill='red'], mjx-mtext[style*='red']");
    if (bad) {
      const why = bad.getAttribute("data-mjx-error") || "undefined macro";
      errors.push(`${why}: ${(sources.get(c) || c.textContent || "?").trim().slice(0, 80)}`);
    }
  }
  return {
    arithmatex: document.querySelectorAll(".arithmatex").length,
    untypeset: Array.from(document.querySelectorAll(".arithmatex"))
      .filter((el) => !el.querySelector("mjx-container")).length,
    containers: containers.length,
    withSvg: containers.filter((c) => c.querySelector("svg")).length,
    missingGlyphs: Array.from(document.querySelectorAll("mjx-container svg use"))
      .map((u) => (u.getAttribute("href") || u.getAttribute("xlink:href") || "").replace(/^#/, ""))
      .filter((id) => id && !document.getElementById(id)).length,
    errors: errors.slice(0, 5),
    nErrors: errors.length,
  };
}
"""

JS_IMAGES = """
async (timeoutMs) => {
  const imgs = Array.from(document.images);
  imgs.forEach((img) => { img.loading = "eager"; });
  const settle = (img) => (img.complete ? Promise.resolve() : new Promise((resolve) => {
    img.addEventListener("load", resolve, { once: true });
    img.addEventListener("error", resolve, { once: true });
  }));
  await Promise.race([
    Promise.all(imgs.map(settle)),
    new Promise((r) => setTimeout(r, timeoutMs)),
  ]);
  return {
    total: imgs.length,
    broken: imgs.filter((i) => !(i.complete && i.naturalWidth > 0))
      .map((i) => (i.currentSrc || i.src || "").slice(0, 120)),
  };
}
"""


WIDTHS = (1400, 900)  # window widths [px] at which the layout is checked; the first is the one pages load at
NO_ALT = "No description has been provided for this image"
RAW_ROLE = r":(?:py:)?(?:mod|class|func|data|meth|attr|exc|obj):`?[~.\w]"

# Text and images of the content: raw roles, images without a description.
JS_CONTENT = """
([rawRole, noDescription]) => {
  const main = document.querySelector(".md-content") || document.body;
  const re = new RegExp(rawRole, "g");
  const roles = (main.innerText.match(re) || []);
  const imgs = Array.from(main.querySelectorAll("img"));
  const noAlt = imgs.filter((i) => {
    const alt = (i.getAttribute("alt") || "").trim();
    return !alt || alt === noDescription;
  });
  return {
    roles: roles.slice(0, 3), nRoles: roles.length,
    noAlt: noAlt.map((i) => (i.getAttribute("src") || "").slice(0, 60)).slice(0, 3), nNoAlt: noAlt.length,
  };
}
"""

# Content cut off on the right of the main column (see the module docstring). MathJax's assistive MathML
# (clipped to 1 px on purpose, for screen readers) and boxes of 1 px or less are not content to read.
JS_CUT = r"""
() => {
  // the column: .md-content (its inner box's margin is part of it: a code span's padding may reach into it)
  const column = document.querySelector(".md-content");
  const main = document.querySelector(".md-content__inner") || column;
  if (!main) return {cut: [], n: 0, pageScroll: 0};
  const limit = column.getBoundingClientRect().right;
  const style = new Map();
  const ox = (el) => { if (!style.has(el)) style.set(el, getComputedStyle(el).overflowX); return style.get(el); };
  const scrolled = (el) => {
    for (let a = el.parentElement; a && a !== main; a = a.parentElement) {
      const o = ox(a);
      if (o === "auto" || o === "scroll") return true;
    }
    return false;
  };
  const name = (el) => {
    const cls = (el.getAttribute("class") || "").trim().split(/\s+/).slice(0, 2).join(".");
    const text = (el.innerText || el.textContent || "").trim().replace(/\s+/g, " ").slice(0, 50);
    return `${el.tagName.toLowerCase()}${cls ? "." + cls : ""} "${text}"`;
  };
  const cut = [];
  for (const el of main.querySelectorAll("*")) {
    if (el.closest("mjx-assistive-mml, .md-clipboard, .md-code__nav, .headerlink")) continue;
    const r = el.getBoundingClientRect();
    if (r.width <= 1 || r.height <= 1) continue;
    const o = ox(el);
    if ((o === "hidden" || o === "clip") && el.scrollWidth > el.clientWidth + 2 && !scrolled(el)) {
      cut.push(`${name(el)} hides ${el.scrollWidth - el.clientWidth} px`);
    } else if (r.right > limit + 1 && !scrolled(el)) {
      cut.push(`${name(el)} reaches ${Math.round(r.right - limit)} px past the column`);
    }
  }
  return {cut: cut.slice(0, 3), n: cut.length,
          pageScroll: document.documentElement.scrollWidth - document.documentElement.clientWidth};
}
"""


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args) -> None:  # the base class signature
        pass


@dataclass
class PageResult:
    url: str
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def html_pages(site: Path) -> list[str]:
    """Site-relative URL paths of every HTML page (``dir/`` for ``dir/index.html``)."""
    pages = []
    for path in sorted(site.rglob("*.html")):
        rel = path.relative_to(site).as_posix()
        if rel.startswith("_check/"):
            continue
        if rel == "index.html":
            pages.append("")
        elif rel.endswith("/index.html"):
            pages.append(rel[: -len("index.html")])
        else:
            pages.append(rel)
    return pages


def serve(site: Path) -> tuple[http.server.ThreadingHTTPServer, str]:
    handler = functools.partial(QuietHandler, directory=str(site))
    server = http.server.ThreadingHTTPServer((HOST, 0), handler)
    threading.Thread(target=server.serve_forever, name="site-server", daemon=True).start()
    return server, f"http://{HOST}:{server.server_address[1]}/"


# On file:// the search worker cannot load (a page opened from disk has an opaque origin): the console
# shows this once per page. Everything else stays an error.
FILE_SEARCH_ERRORS = (
    "Failed to construct 'Worker'",
    "search_index.json",
    "worker",
)


def local(url: str) -> bool:
    """A request that stays on this machine: the test server, or a file of the site (``file://``)."""
    parts = urlsplit(url)
    return parts.hostname == HOST or parts.scheme in ("file", "data", "blob")


def watch(page, result: PageResult, from_disk: bool = False) -> None:
    """Record failed requests, external requests, HTTP errors and console errors of ``page``."""
    blocked: set[str] = set()

    def external(url: str) -> None:
        if url not in blocked:
            blocked.add(url)
            result.problems.append(f"external request (blocked): {url[:160]}")

    def route(route) -> None:
        url = route.request.url
        if local(url):
            route.continue_()
        else:
            external(url)
            route.abort("blockedbyclient")

    def on_request_failed(request) -> None:
        if from_disk and "search" in request.url:
            result.notes.append("search needs a server")
            return
        if request.url not in blocked:
            result.problems.append(f"request failed ({request.failure}): {request.url[:160]}")

    def on_response(response) -> None:
        if response.status >= 400:
            result.problems.append(f"HTTP {response.status}: {response.url[:160]}")

    def on_console(msg) -> None:
        if msg.type == "error":
            if "ERR_BLOCKED_BY_CLIENT" in msg.text and blocked:
                return  # the console's echo of a request aborted above, already reported
            if from_disk and any(key in msg.text for key in FILE_SEARCH_ERRORS):
                result.notes.append("search needs a server")
                return
            result.problems.append(f"console error: {msg.text[:300]}")

    def on_page_error(exc) -> None:
        if from_disk and any(key in str(exc) for key in FILE_SEARCH_ERRORS):
            result.notes.append("search needs a server")
            return
        result.problems.append(f"uncaught exception: {str(exc)[:300]}")

    def on_request(request) -> None:
        url = request.url
        if url.startswith(("http:", "https:", "ws:", "wss:")) and not local(url):
            external(url)

    page.route("**/*", route)
    page.on("request", on_request)
    page.on("requestfailed", on_request_failed)
    page.on("response", on_response)
    page.on("console", on_console)
    page.on("pageerror", on_page_error)


def check_content(page, result: PageResult) -> None:
    """No raw Sphinx role in the text; every image of the content described."""
    state = page.evaluate(JS_CONTENT, [RAW_ROLE, NO_ALT])
    if state["nRoles"]:
        result.problems.append(f"{state['nRoles']} raw Sphinx role(s) in the text, e.g. {state['roles']}")
    if state["nNoAlt"]:
        result.problems.append(
            f"{state['nNoAlt']} image(s) without a description (alt), e.g. {state['noAlt']}"
        )


def check_layout(page, result: PageResult) -> None:
    """At each width of WIDTHS (the page resized in place): nothing cut off on the right of the column."""
    for width in WIDTHS:
        size = page.viewport_size or {"height": 900}
        if size.get("width") != width:
            page.set_viewport_size({"width": width, "height": size["height"]})
            page.wait_for_timeout(300)
        state = page.evaluate(JS_CUT)
        if state["n"]:
            result.problems.append(f"at {width} px, {state['n']} element(s) cut off on the right, e.g. {state['cut']}")
        if state["pageScroll"] > 1:
            result.problems.append(f"at {width} px, the page scrolls sideways by {state['pageScroll']} px")
    page.set_viewport_size({"width": WIDTHS[0], "height": (page.viewport_size or {"height": 900})["height"]})


def check_math(page, result: PageResult, require: bool) -> None:
    status = page.evaluate(JS_WAIT_MATHJAX % PAGE_TIMEOUT_MS)
    if status == "timeout":
        result.problems.append("MathJax did not finish typesetting")
        return
    state = page.evaluate(JS_MATH_STATE)
    require = require or state["arithmatex"] > 0
    for error in state["errors"]:
        result.problems.append(f"MathJax error: {error}")
    if state["nErrors"] > len(state["errors"]):
        result.problems.append(f"... {state['nErrors'] - len(state['errors'])} more MathJax errors")
    if state["untypeset"]:
        result.problems.append(
            f"{state['untypeset']} of {state['arithmatex']} arithmatex elements not typeset"
        )
    if require:
        if status != "typeset":
            result.problems.append("page has math but MathJax is not loaded")
        elif state["containers"] == 0:
            result.problems.append("no typeset math (mjx-container) on the page")
        elif state["withSvg"] < state["containers"]:
            result.problems.append(f"{state['containers'] - state['withSvg']} mjx-container without SVG")
    if state["missingGlyphs"]:
        result.problems.append(f"{state['missingGlyphs']} SVG glyph references without a definition")
    if state["containers"]:
        result.notes.append(f"{state['containers']} formulas")


# Every link of the page to another page or file of the site, as the browser resolved it.
JS_LINKS = """
() => Array.from(document.querySelectorAll("a[href]"))
  .map((a) => a.href)
  .filter((h) => h.startsWith("file:"))
"""


def check_links_on_disk(page, result: PageResult) -> None:
    """Each ``file://`` link of the page names an existing file (not a directory: on disk a browser
    shows a directory as a listing, not as its index.html)."""
    bad = []
    for href in dict.fromkeys(page.evaluate(JS_LINKS)):
        path = Path(unquote(urlsplit(href).path))
        if not path.is_file():
            bad.append(href)
    for href in bad[:5]:
        result.problems.append(f"link does not resolve to a file from disk: {href[:160]}")
    if len(bad) > 5:
        result.problems.append(f"... {len(bad) - 5} more links that do not resolve from disk")


def check_page(context, base: str, rel: str, site: Path, from_disk: bool = False) -> PageResult:
    url = base + rel
    if from_disk and (rel == "" or rel.endswith("/")):
        url += "index.html"
    result = PageResult(url)
    page = context.new_page()
    page.set_default_timeout(PAGE_TIMEOUT_MS)
    watch(page, result, from_disk)
    try:
        response = page.goto(url, wait_until="load", timeout=PAGE_TIMEOUT_MS)
        if from_disk:
            check_links_on_disk(page, result)
        elif response is None or not response.ok:
            status = response.status if response is not None else "no response"
            if not any(p.startswith("HTTP ") for p in result.problems):
                result.problems.append(f"page load: {status}")
        try:
            page.wait_for_load_state("networkidle", timeout=PAGE_TIMEOUT_MS)
        except Exception:
            result.notes.append("network not idle after 30 s")
        check_math(page, result, require=any(key in rel for key in MATH_PAGES))
        images = page.evaluate(JS_IMAGES, PAGE_TIMEOUT_MS)
        for src in images["broken"]:
            result.problems.append(f"image not loaded: {src}")
        if images["total"]:
            result.notes.append(f"{images['total']} images")
        check_content(page, result)
        check_layout(page, result)
        if any(key in rel for key in SCREENSHOT_PAGES) and not from_disk:
            shot = site / "_check" / f"{next(k for k in SCREENSHOT_PAGES if k in rel)}.png"
            shot.parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(shot), full_page=True, timeout=PAGE_TIMEOUT_MS)
            result.notes.append(f"screenshot {shot}")
        page.wait_for_timeout(200)  # let late console messages arrive
    except Exception as exc:
        result.problems.append(f"{type(exc).__name__}: {str(exc).splitlines()[0][:300]}")
    finally:
        page.close()
    return result


def check_instant_navigation(context, base: str, target: str) -> PageResult:
    """Home page -> click the nav link to ``target``: material swaps the content (no reload)."""
    result = PageResult(f"{base} -> {target} (instant navigation)")
    page = context.new_page()
    page.set_default_timeout(PAGE_TIMEOUT_MS)
    watch(page, result)
    try:
        page.goto(base, wait_until="load", timeout=PAGE_TIMEOUT_MS)
        page.evaluate(JS_WAIT_MATHJAX % PAGE_TIMEOUT_MS)
        page.evaluate("() => { window.__noReload = true; }")
        link = page.locator(f"a.md-nav__link[href$='{target}']").first
        link.click(timeout=PAGE_TIMEOUT_MS)
        page.wait_for_url(f"**/{target}", timeout=PAGE_TIMEOUT_MS)
        page.wait_for_load_state("networkidle", timeout=PAGE_TIMEOUT_MS)
        if not page.evaluate("() => window.__noReload === true"):
            result.notes.append("page was reloaded (instant navigation off)")
        check_math(page, result, require=True)
        page.wait_for_timeout(200)
    except Exception as exc:
        result.problems.append(f"{type(exc).__name__}: {str(exc).splitlines()[0][:300]}")
    finally:
        page.close()
    return result


def instant_navigation(site: Path) -> bool:
    """Whether the site enables material's ``navigation.instant`` (read from the home page)."""
    index = site / "index.html"
    text = index.read_text(encoding="utf-8", errors="replace") if index.is_file() else ""
    match = re.search(r'<script id="__config" type="application/json">(.*?)</script>', text, re.DOTALL)
    try:
        return "navigation.instant" in json.loads(match.group(1)).get("features", []) if match else False
    except ValueError:
        return False


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("site_dir", type=Path, help="the built site (mkdocs site_dir)")
    args = parser.parse_args(argv)
    site = args.site_dir.resolve()
    pages = html_pages(site) if site.is_dir() else []
    if not pages:
        print(f"browser check: no HTML pages under {site}", file=sys.stderr)
        return 2

    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    if not os.access(chromium, os.X_OK):
        print(f"browser check: chromium not found ({chromium}); apt-get install chromium", file=sys.stderr)
        return 2
    os.environ.setdefault("PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD", "1")

    server, base = serve(site)
    results: list[PageResult] = []
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS, headless=True)
            try:
                context = browser.new_context(
                    viewport={"width": WIDTHS[0], "height": 900}, service_workers="block"
                )
                for rel in pages:
                    results.append(check_page(context, base, rel, site))
                    print_result(results[-1])
                targets = [rel for rel in pages if any(key in rel for key in SCREENSHOT_PAGES)]
                if targets and instant_navigation(site):
                    results.append(check_instant_navigation(context, base, targets[0]))
                    print_result(results[-1])
                disk = site.as_uri() + "/"
                for rel in pages:
                    if rel.startswith("search") or rel == "404.html":
                        continue  # served only: the search page, and the 404 page (root-relative links)
                    results.append(check_page(context, disk, rel, site, from_disk=True))
                    print_result(results[-1])
                context.close()
            finally:
                browser.close()
    finally:
        server.shutdown()
        server.server_close()

    failed = sum(1 for r in results if r.problems)
    print(f"browser check: {len(results) - failed} passed, {failed} failed")
    return 1 if failed else 0


def print_result(result: PageResult) -> None:
    if result.problems:
        print(f"FAIL {result.url}")
        for problem in dict.fromkeys(result.problems):
            print(f"     - {problem}")
    else:
        notes = f"  ({', '.join(dict.fromkeys(result.notes))})" if result.notes else ""
        print(f"OK   {result.url}{notes}")
    sys.stdout.flush()


if __name__ == "__main__":
    sys.exit(main())
