"""The Python API page shows no raw Sphinx role text: docs/hooks/sphinx_roles.py turns ``:func:`~a.b```
into an autorefs link where the site documents the target, else into code.

A unit test of the converter, and the API page itself built with the site's mkdocstrings configuration
(mkdocs.yml, the notebooks and the other pages left out: seconds): before the extension the page held 33
raw roles (``:mod:~motionsig_cli.signals.gf2``).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tests.docs_hooks import load_hook

ROOT = Path(__file__).resolve().parents[1]
HOOK = ROOT / "docs" / "hooks" / "sphinx_roles.py"
RAW_ROLE = re.compile(r":(?:py:)?(?:mod|class|func|data|meth|attr|exc|obj):`?[~.\w]")


def _hook():
    return load_hook("sphinx_roles")


DOCUMENTED = {"motionsig_cli.records.grid_period", "motionsig_cli.config.ConfigError", "pkg.mod.f"}


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (":func:`~motionsig_cli.records.grid_period`", "[`grid_period`][motionsig_cli.records.grid_period]"),
        (":func:`motionsig_cli.records.grid_period`",
         "[`motionsig_cli.records.grid_period`][motionsig_cli.records.grid_period]"),
        (":mod:`~motionsig_cli.signals.gf2`", "`gf2`"),  # not on the site: code
        (":class:`motionsig_cli.ConfigError`", "[`motionsig_cli.ConfigError`][motionsig_cli.config.ConfigError]"),
        (":data:`.JITTER_TOL`", "`JITTER_TOL`"),
        (":func:`.f`", "[`f`][pkg.mod.f]"),  # relative to the docstring's module
        (":meth:`f`", "[`f`][pkg.mod.f]"),  # bare: the module, then the class
        (":attr:`~Thing.attr`", "`attr`"),
        (":py:func:`title <pkg.mod.f>`", "[`title`][pkg.mod.f]"),
        ("no role, ``code`` and :math: stay", "no role, ``code`` and :math: stay"),
    ],
)  # fmt: skip
def test_converter(text: str, expected: str) -> None:
    aliases = {"motionsig_cli.ConfigError": "motionsig_cli.config.ConfigError"}
    out = _hook().convert(text, DOCUMENTED, module="pkg.mod", parent="pkg.mod.Thing", aliases=aliases)
    assert out == expected
    assert not RAW_ROLE.search(out)


def test_documented_targets_are_the_api_pages() -> None:
    import motionsig_cli

    targets = _hook().documented_targets()
    assert targets == {f"{m}.{n}" for n, m in motionsig_cli._PUBLIC.items()}


@pytest.mark.slow
def test_built_api_page_has_no_raw_roles_and_links_documented_targets(tmp_path: Path) -> None:
    pytest.importorskip("mkdocs")
    pytest.importorskip("mkdocstrings_handlers.python")

    class Loader(yaml.SafeLoader):
        pass

    Loader.add_multi_constructor("", lambda loader, suffix, node: None)  # !!python/name tags etc.
    cfg = yaml.load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"), Loader=Loader)
    plugins = [p for p in cfg["plugins"] if not (isinstance(p, dict) and "mkdocs-jupyter" in p)]
    python = next(p for p in plugins if isinstance(p, dict) and "mkdocstrings" in p)
    options = python["mkdocstrings"]["handlers"]["python"]["options"]
    assert "docs/hooks/sphinx_roles.py:SphinxRoles" in options["extensions"]
    options["extensions"] = [f"{HOOK}:SphinxRoles"]
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "api.md").write_text((ROOT / "docs" / "api.md").read_text(encoding="utf-8"), encoding="utf-8")
    (docs / "sources.md").write_text("# Sources\n", encoding="utf-8")  # the one page api.md links to
    cfg.update(
        docs_dir=str(docs), site_dir=str(tmp_path / "site"), nav=[{"API": "api.md"}, {"Sources": "sources.md"}],
        plugins=plugins, hooks=[], extra_javascript=[], extra_css=[], exclude_docs="", watch=[],
        theme={"name": "material", "font": False},
    )  # fmt: skip
    config = tmp_path / "mkdocs.yml"
    config.write_text(yaml.safe_dump(cfg, allow_unicode=True), encoding="utf-8")
    run = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(config)],
        cwd=ROOT, capture_output=True, text=True, env={"NO_MKDOCS_2_WARNING": "1", "PATH": "/usr/bin:/bin"},
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]
    html = (tmp_path / "site" / "api.html").read_text(encoding="utf-8")
    text = re.sub(r"<[^>]+>", "", html)
    assert not RAW_ROLE.search(text), RAW_ROLE.findall(text)[:5]
    # a role whose target the page documents is a link to it (gold_family's docstring names gold_code)
    assert re.search(
        r'<a class="autorefs autorefs-internal"[^>]*href="#motionsig_cli\.signals\.gold\.gold_code"', html
    )
