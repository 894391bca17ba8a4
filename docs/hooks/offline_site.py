"""MkDocs hook: keep the built site offline.

* Before the build: MathJax (``docs/javascripts/mathjax/tex-svg.js``, fetched by
  ``scripts/fetch_mathjax.sh``) must be present.
* Notebook pages (mkdocs-jupyter / nbconvert HTML): remove the notebook's own MathJax 2 loader and
  configuration block (the site loads MathJax 3 for every page, see ``mkdocs.yml``
  ``extra_javascript``) and nbconvert's mermaid.js loader, whose module script names cdnjs URLs
  (it would only import them for mermaid diagrams, which these notebooks do not use).
* After rendering each page: fail the build if the HTML still mentions a CDN or loads any
  resource (script, stylesheet, image, frame, media) from another host. Plain hyperlinks to other
  sites are fine.
* After the build: scan every text file of the site for CDN hosts. Vendored third-party bundles
  carry a few URLs that are never requested here; they are listed in ``DORMANT`` (file pattern,
  exact URL) with the reason, and anything else fails the build.
"""

from __future__ import annotations

import logging
import re
from pathlib import Path
from typing import Any

from mkdocs.exceptions import PluginError

log = logging.getLogger("mkdocs.hooks.offline_site")

MATHJAX = Path("javascripts/mathjax/tex-svg.js")
FETCH_HINT = "bash scripts/fetch_mathjax.sh docs/javascripts/mathjax/tex-svg.js"

CDN_RE = re.compile(
    r"(?:cdnjs\.cloudflare\.com|unpkg\.com|jsdelivr\.net|googleapis\.com|gstatic\.com|code\.jquery\.com"
    r"|cdn\.plot\.ly|cdn\.bokeh\.org|polyfill\.io)",
    re.IGNORECASE,
)
URL_LEFT = re.compile(r"[\w:/.@-]*$")  # scheme, slashes and subdomains before a CDN host name
URL_RIGHT = re.compile(r"[^\"'`\s)\\<>]*")  # path after it
EXTERNAL_RESOURCE_RE = re.compile(
    r"<(?:script|link|img|iframe|source|video|audio|embed|object)\b[^>]*?"
    r"\b(?:src|href|data|srcset)\s*=\s*[\"']?\s*(?:https?:)?//[^\"'\s>]*",
    re.IGNORECASE,
)
TEXT_SUFFIXES = {".html", ".js", ".css", ".json", ".map", ".xml", ".txt", ".svg", ".py", ".mjs"}
# URLs inside vendored JavaScript that are only requested in situations that do not arise here.
DORMANT: dict[str, set[str]] = {
    # material's bundle: a ResizeObserver polyfill for browsers without it, and mermaid.js for pages
    # with mermaid diagrams (superfences has no mermaid fence configured).
    "assets/javascripts/bundle.*.min.js*": {
        "https://unpkg.com/resize-observer-polyfill",
        "https://unpkg.com/mermaid@11/dist/mermaid.min.js",
        "unpkg.com.",  # a source comment in the .map: "polyfill is automatically downloaded from unpkg.com."
    },
    # MathJax: defaults of the bundled speech-rule-engine (MathJax itself points SRE at
    # [mathjax]/sre/mathmaps) and its Internet Explorer XPath shim.
    "javascripts/mathjax/tex-svg.js": {
        "https://cdn.jsdelivr.net/npm/speech-rule-engine@",
        "https://cdn.jsdelivr.net/npm/sre-mathmaps-ie@",
        "https://cdn.jsdelivr.net/npm/wicked-good-xpath@1.3.0/dist/wgxpath.install.js",
    },
}
# nbconvert base/mathjax.html.j2: "<!-- Load mathjax -->" ... "<!-- End of mathjax configuration -->"
NB_MATHJAX_RE = re.compile(r"<!-- Load mathjax -->.*?<!-- End of mathjax configuration -->", re.DOTALL)
# nbconvert lab/mermaidjs.html.j2: one <script type="module"> that imports mermaid on demand
NB_MERMAID_RE = re.compile(
    r"<script type=\"module\">(?:(?!</script>).)*?mermaid(?:(?!</script>).)*?</script>", re.DOTALL
)


def on_config(config: Any) -> Any:
    mathjax = Path(config["docs_dir"]) / MATHJAX
    if not mathjax.is_file():
        raise PluginError(f"{mathjax} is missing: run `{FETCH_HINT}` (or `make docs`)")
    return config


def _is_notebook(page: Any) -> bool:
    return page.file.src_uri.endswith((".py", ".ipynb"))


def on_page_content(html: str, page: Any, config: Any, files: Any) -> str:
    if not _is_notebook(page):
        return html
    html, n_mathjax = NB_MATHJAX_RE.subn("", html)
    html = NB_MERMAID_RE.sub("", html)
    mathjax_url = _plugin_option(config, "custom_mathjax_url")
    if mathjax_url and f'src="{mathjax_url}"' in html:
        raise PluginError(
            f"offline_site hook: {page.file.src_uri}: could not remove the notebook's MathJax loader "
            f"(found {n_mathjax} loader blocks; did the mkdocs-jupyter/nbconvert template change?)"
        )
    return html


def on_post_page(output: str, page: Any, config: Any) -> str:
    problems = sorted({m.group(0) for m in CDN_RE.finditer(output)})
    problems += sorted(
        {
            m.group(0)[:160]
            for m in EXTERNAL_RESOURCE_RE.finditer(output)
            if not re.search(r"rel=[\"']?(?:canonical|alternate)", m.group(0))
        }
    )
    if problems:
        raise PluginError(
            f"offline_site hook: {page.file.src_uri} refers to external resources: " + "; ".join(problems)
        )
    return output


def _plugin_option(config: Any, name: str) -> Any:
    plugin = config["plugins"].get("mkdocs-jupyter")
    return plugin.config.get(name) if plugin is not None else None


def on_post_build(config: Any) -> None:
    site = Path(config["site_dir"])
    problems, dormant = [], 0
    for path in sorted(site.rglob("*")):
        if not path.is_file() or path.suffix not in TEXT_SUFFIXES:
            continue
        rel = path.relative_to(site)
        text = path.read_text(encoding="utf-8", errors="replace")
        if not CDN_RE.search(text):
            continue
        allowed = set().union(*(urls for pattern, urls in DORMANT.items() if rel.match(pattern)))
        for url in sorted({_url_at(text, m.start(), m.end()) for m in CDN_RE.finditer(text)}):
            if url in allowed:
                dormant += 1
            else:
                problems.append(f"{rel}: {url}")
    if problems:
        raise PluginError("offline_site hook: CDN references in the built site:\n  " + "\n  ".join(problems))
    log.info("offline_site: no CDN references in %s (%d known dormant URLs in vendored JS)", site, dormant)


def _url_at(text: str, start: int, end: int) -> str:
    """The URL (or bare host reference) around the CDN host name at ``text[start:end]``."""
    left = URL_LEFT.search(text, max(0, start - 100), start)
    right = URL_RIGHT.match(text, end)
    return text[left.start() if left else start : right.end() if right else end]
