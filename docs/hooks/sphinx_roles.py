"""Griffe extension (mkdocstrings' Python handler, ``extensions:`` in mkdocs.yml): the Sphinx roles of the
docstrings, as rendered on the Python API page.

The docstrings cross-reference with Sphinx roles — ``:func:`~motionsig_cli.records.grid_period```,
``:class:`ConfigError```, ``:data:`.JITTER_TOL``` — which Markdown would show as raw text
(``:mod:~motionsig_cli.signals.gf2``). Each docstring is rewritten when griffe loads it:

* the role's target is resolved: an absolute name as written; a name of the package itself
  (``motionsig_cli.ConfigError``) to the module that defines it (``motionsig_cli._PUBLIC``); a relative or
  bare name (``.name``, ``name``) against the docstring's own module, then its class;
* a target documented on the site (a ``::: identifier`` of docs/api.md) becomes an autorefs link,
  ``[`grid_period`][motionsig_cli.records.grid_period]``, which mkdocs-autorefs resolves (strict mode:
  an unresolved link would fail the build, so nothing else is linked);
* anything else becomes plain code, ``` `grid_period` ```.

The text shown is the target as written, without the leading ``.``; with ``~``, its last component
(Sphinx's convention).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Collection
from pathlib import Path
from typing import Any

ROLE = re.compile(r":(?:py:)?(mod|class|func|data|meth|attr|exc|obj|const):`([^`]+)`")
"""A Sphinx role: ``:kind:`target``` (``py:`` domain prefix allowed)."""
API_PAGE = Path(__file__).resolve().parents[1] / "api.md"


def documented_targets(page: Path = API_PAGE) -> frozenset[str]:
    """The identifiers the API page documents (its ``::: identifier`` lines)."""
    return frozenset(re.findall(r"^::: (\S+)\s*$", page.read_text(encoding="utf-8"), flags=re.M))


def _package_aliases() -> dict[str, str]:
    """``motionsig_cli.NAME`` -> the defining module's ``module.NAME``, for the public names."""
    try:
        import motionsig_cli
    except ImportError:  # pragma: no cover - the docs build always has the package
        return {}
    return {f"motionsig_cli.{n}": f"{m}.{n}" for n, m in motionsig_cli._PUBLIC.items()}


def convert(
    text: str,
    documented: Collection[str],
    *,
    module: str = "",
    parent: str = "",
    aliases: dict[str, str] | None = None,
) -> str:
    """``text`` with every Sphinx role replaced by an autorefs link (a documented target) or code.

    Args:
        text: a docstring.
        documented: the identifiers documented on the site.
        module: the dotted path of the docstring's module (resolves relative and bare targets).
        parent: the dotted path of the docstring's class, if any (resolves a method's ``:meth:`other```).
        aliases: public package names to their defining path (default: ``motionsig_cli._PUBLIC``'s).

    Examples:
        >>> convert(":func:`~a.b.f` and :class:`a.C`", {"a.b.f"})
        '[`f`][a.b.f] and `a.C`'
    """
    table = _package_aliases() if aliases is None else aliases

    def resolve(name: str, relative: bool) -> str | None:
        candidates = [] if relative else [name, table.get(name, "")]
        for scope in (module, parent):
            if scope:
                candidates.append(f"{scope}.{name}")
        return next((c for c in candidates if c and c in documented), None)

    def replace(m: re.Match[str]) -> str:
        raw = m.group(2).strip()
        if "<" in raw and raw.endswith(">"):  # :func:`title <target>`
            title, _, target = raw[:-1].partition("<")
            title, raw = title.strip(), target.strip()
        else:
            title = ""
        short = raw.startswith("~")
        name = raw.lstrip("~")
        relative = name.startswith(".")
        name = name.lstrip(".")
        shown = title or (name.rsplit(".", 1)[-1] if short else name)
        target = resolve(name, relative)
        return f"[`{shown}`][{target}]" if target else f"`{shown}`"

    return ROLE.sub(replace, text)


def _make_extension() -> type | None:
    try:
        import griffe
    except ImportError:  # pragma: no cover - the docs build always has griffe
        return None

    class SphinxRoles(griffe.Extension):
        """Rewrite the Sphinx roles of every docstring griffe loads (module docstring)."""

        def __init__(self) -> None:
            super().__init__()
            self.documented = documented_targets()
            self.aliases = _package_aliases()

        def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
            if obj.docstring is None:
                return
            module = obj.module.path if not obj.is_module else obj.path
            parent = obj.parent.path if (obj.parent is not None and obj.parent.is_class) else ""
            obj.docstring.value = convert(
                obj.docstring.value, self.documented, module=module, parent=parent, aliases=self.aliases
            )

    return SphinxRoles


SphinxRoles: Callable[..., Any] | None = _make_extension()
