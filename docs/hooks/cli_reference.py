"""MkDocs hook: the CLI reference page, generated from the typer app at every build.

``docs/cli.md`` holds the marker ``<!-- cli-reference -->``; this hook replaces it with one section
per command of ``typer.main.get_command(motionsig_cli.cli.app.app)``, walking nested groups
recursively: a heading with the full command path (explicit, unique anchor), the usage line, the
help text (``\\b`` paragraphs, i.e. the worked examples, become code blocks), the subcommands of a
group, and a table of arguments and options (names, type, default, help).

The markdown is produced in a fresh interpreter (this file run as a script, with the repository
root first on ``sys.path``), so every build — ``mkdocs serve`` rebuilds included — sees the current
CLI code, and importing the package cannot disturb the MkDocs process. Run it by hand to see the
generated markdown: ``.venv/bin/python docs/hooks/cli_reference.py``.
"""

from __future__ import annotations

import enum
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

MARKER = "<!-- cli-reference -->"
PAGE = "cli.md"
APP = ("motionsig_cli.cli.app", "app")  # module, attribute of the typer.Typer instance
PROG = "motionsig"
REPO_ROOT = Path(__file__).resolve().parents[2]


# --------------------------------------------------------------------------- MkDocs side


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    if page.file.src_uri != PAGE:
        return markdown
    from mkdocs.exceptions import PluginError

    if MARKER not in markdown:
        raise PluginError(f"cli_reference hook: {PAGE} lacks the marker {MARKER}")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO_ROOT), env.get("PYTHONPATH")]))
    env.setdefault("MPLBACKEND", "Agg")
    proc = subprocess.run(
        [sys.executable, str(Path(__file__).resolve())],
        capture_output=True,
        text=True,
        cwd=REPO_ROOT,
        env=env,
        timeout=300,
        check=False,
    )
    if proc.returncode != 0 or not proc.stdout.strip():
        raise PluginError(
            f"cli_reference hook: generating the CLI reference failed (exit {proc.returncode}):\n"
            f"{proc.stderr.strip()}"
        )
    return markdown.replace(MARKER, proc.stdout, 1)


# --------------------------------------------------------------------------- generator side

_SLUG_RE = re.compile(r"[^a-z0-9]+")


def anchor(path: str) -> str:
    """Explicit heading id for a command path: ``motionsig encode gold`` -> ``motionsig-encode-gold``."""
    return _SLUG_RE.sub("-", path.lower()).strip("-")


def escape_md(text: str) -> str:
    """Plain help text -> inline markdown that renders literally (backtick code spans kept)."""
    text = text.replace("\\", "\\\\").replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    for ch in "*_[]{}|":
        text = text.replace(ch, "\\" + ch)
    return text


def code_span(text: str) -> str:
    ticks = "``" if "`" in text else "`"
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{ticks}{pad}{text}{pad}{ticks}"


def fence(lines: list[str], lang: str = "text") -> str:
    body = "\n".join(lines).rstrip()
    ticks = "```"
    while ticks in body:
        ticks += "`"
    return f"{ticks}{lang}\n{body}\n{ticks}"


def _dedent(lines: list[str]) -> list[str]:
    indents = [len(line) - len(line.lstrip()) for line in lines if line.strip()]
    cut = min(indents, default=0)
    return [line[cut:] for line in lines]


def _code_lang(lines: list[str]) -> str:
    body = [line.strip() for line in lines if line.strip()]
    is_shell = all(line.startswith((f"{PROG} ", "$ ", "# ")) for line in body)
    return "bash" if body and is_shell else "text"


def render_help(text: str) -> str:
    """Click help text -> markdown.

    Paragraphs are separated by blank lines. A paragraph introduced by a ``\\b`` line is kept
    verbatim by click; it becomes a code block here, after an optional lead-in line such as
    ``Example:`` (a first line ending in ``:`` followed by indented lines). An indented
    paragraph is also kept as code; every other paragraph is re-flowed into one line of text.
    Everything after a ``\\f`` line is not part of the help (click's convention).
    """
    text = text.partition("\f")[0]
    paragraphs: list[list[str]] = [[]]
    for line in text.expandtabs().splitlines():
        if line.strip():
            paragraphs[-1].append(line.rstrip())
        elif paragraphs[-1]:
            paragraphs.append([])
    out: list[str] = []
    for para in filter(None, paragraphs):
        verbatim = para[0].strip() == "\b"
        if verbatim:
            para = para[1:]
            if not para:
                continue
        if verbatim or all(line.startswith(" ") for line in para):
            lead = para[0]
            if (
                len(para) > 1
                and lead.rstrip().endswith(":")
                and not lead.startswith(" ")
                and para[1][:1] == " "
            ):
                out.append(escape_md(lead.strip()))
                para = para[1:]
            block = _dedent(para)
            out.append(fence(block, _code_lang(block)))
        else:
            out.append(escape_md(" ".join(line.strip() for line in para)))
    return "\n\n".join(out)


def _plain(value: Any) -> str:
    if isinstance(value, enum.Enum):
        value = value.value
    if isinstance(value, (list, tuple)):
        return ", ".join(_plain(v) for v in value)
    return str(value)


def param_names(param: Any) -> str:
    if getattr(param, "param_type_name", "") == "argument":
        name = getattr(param, "display_name_raw", None) or param.metavar or param.name
        return code_span(str(name)) + (" …" if param.nargs != 1 else "")
    groups = [", ".join(code_span(o) for o in sorted(param.opts, key=len))]
    if getattr(param, "secondary_opts", None):
        groups.append(", ".join(code_span(o) for o in param.secondary_opts))
    return " / ".join(groups)


def param_type(param: Any, ctx: Any) -> str:
    if getattr(param, "count", False):
        return "count"
    if getattr(param, "is_flag", False):
        return "flag"
    label = None
    if getattr(param, "metavar", None):
        label = param.metavar
    elif hasattr(param, "display_type"):  # typer >= 0.2x, vendored click
        label = param.display_type(ctx)
        if label and label.startswith("<") and label.endswith(">"):
            label = label[1:-1]
    elif hasattr(param, "type"):  # classic click
        choices = getattr(param.type, "choices", None)
        label = "|".join(_plain(c) for c in choices) if choices else param.type.name
    label = label or "text"
    choices = label.split("|") if "|" in label and not label.startswith("list[") else None
    cell = " \\| ".join(code_span(c) for c in choices) if choices else escape_md(label)
    range_fn = getattr(param, "_get_number_range_help_str", None)
    if callable(range_fn):
        rng = range_fn()
        if rng:
            cell += f" ({escape_md(rng)})"
    if getattr(param, "multiple", False):
        cell += ", repeatable"
    elif getattr(param, "nargs", 1) not in (1, None) and getattr(param, "param_type_name", "") == "option":
        cell += f" × {param.nargs}"
    return cell


def param_default(param: Any, ctx: Any) -> str:
    if getattr(param, "required", False):
        return "*required*"
    if isinstance(getattr(param, "show_default", None), str):
        return escape_md(param.show_default)
    try:
        resilient, ctx.resilient_parsing = ctx.resilient_parsing, True
        try:
            value = param.get_default(ctx, call=False)
        finally:
            ctx.resilient_parsing = resilient
    except Exception:
        value = getattr(param, "default", None)
    if callable(value):
        return "(dynamic)"
    if getattr(param, "is_flag", False) and not getattr(param, "count", False):
        if getattr(param, "secondary_opts", None):
            opts = param.opts if value else param.secondary_opts
            return code_span(opts[0]) if opts else ""
        return "" if param.name == "help" or value is None else code_span(str(bool(value)).lower())
    if value is None or value == "" or value == () or value == []:
        return ""
    return code_span(_plain(value))


def param_help(param: Any) -> str:
    text = " ".join((getattr(param, "help", None) or "").split())
    extra = []
    envvar = getattr(param, "envvar", None)
    if envvar:
        names = [envvar] if isinstance(envvar, str) else list(envvar)
        extra.append("env: " + ", ".join(code_span(n) for n in names))
    if getattr(param, "deprecated", False):
        extra.append("deprecated")
    return " ".join([escape_md(text), *(f"({e})" for e in extra)]).strip()


def params_table(params: list[Any], ctx: Any, first: str) -> list[str]:
    rows = [f"| {first} | Type | Default | Description |", "| --- | --- | --- | --- |"]
    for p in params:
        cells = [param_names(p), param_type(p, ctx), param_default(p, ctx), param_help(p)]
        rows.append("| " + " | ".join(c.replace("\n", " ") or " " for c in cells) + " |")
    return rows


def make_context(cmd: Any, name: str, parent: Any) -> Any:
    settings = dict(getattr(cmd, "context_settings", None) or {})
    return cmd.context_class(cmd, info_name=name, parent=parent, **settings)


def subcommands(cmd: Any, ctx: Any) -> list[tuple[str, Any]]:
    if not hasattr(cmd, "list_commands"):
        return []
    out = []
    for name in cmd.list_commands(ctx):
        sub = cmd.get_command(ctx, name)
        if sub is not None and not getattr(sub, "hidden", False):
            out.append((name, sub))
    return out


def render_command(cmd: Any, name: str, parent: Any, depth: int) -> list[str]:
    ctx = make_context(cmd, name, parent)
    path = ctx.command_path
    level = "#" * min(2 + depth, 6)
    out = [f"{level} {code_span(path)} {{ #{anchor(path)} }}", ""]
    if getattr(cmd, "deprecated", False):
        out += ['!!! warning "Deprecated"', "", "    This command is deprecated.", ""]
    usage = " ".join([path, *cmd.collect_usage_pieces(ctx)])
    out += [fence([f"Usage: {usage}"]), ""]
    if cmd.help:
        out += [render_help(cmd.help), ""]
    subs = subcommands(cmd, ctx)
    if subs:
        out += ["**Commands**", "", "| Command | Description |", "| --- | --- |"]
        for sub_name, sub in subs:
            sub_path = f"{path} {sub_name}"
            short = sub.get_short_help_str(limit=120) if hasattr(sub, "get_short_help_str") else ""
            out.append(f"| [{code_span(sub_name)}](#{anchor(sub_path)}) | {escape_md(short)} |")
        out.append("")
    params = [p for p in cmd.get_params(ctx) if not getattr(p, "hidden", False)]
    arguments = [p for p in params if getattr(p, "param_type_name", "") == "argument"]
    options = [p for p in params if getattr(p, "param_type_name", "") != "argument"]
    if arguments:
        out += ["**Arguments**", "", *params_table(arguments, ctx, "Argument"), ""]
    if options:
        out += ["**Options**", "", *params_table(options, ctx, "Option"), ""]
    if getattr(cmd, "epilog", None):
        out += [render_help(cmd.epilog), ""]
    for sub_name, sub in subs:
        out += render_command(sub, sub_name, ctx, depth + 1)
    return out


def render_reference() -> str:
    import importlib

    import typer.main

    app = getattr(importlib.import_module(APP[0]), APP[1])
    root = typer.main.get_command(app)
    lines = render_command(root, PROG, None, 0)
    # The whole reference is code and option names, never math: keep MathJax out of it.
    return (
        '<div class="cli-reference mathjax_ignore" markdown="1">\n\n'
        + "\n".join(lines).rstrip()
        + "\n\n</div>\n"
    )


if __name__ == "__main__":
    sys.stdout.write(render_reference())
    sys.stdout.flush()
