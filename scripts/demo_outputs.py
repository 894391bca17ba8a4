"""Run every ``motionsig`` command of ``make demo`` and record its outputs, or compare two records.

A refactoring must not change a result. This script reads the ``demo`` recipe of the Makefile, runs
each ``motionsig`` line (pipes included) with the package found first on ``--root`` (a checkout),
and stores standard output and every table the line writes (``-o FILE``) under ``DIR``::

    python scripts/demo_outputs.py record DIR [--root CHECKOUT]
    python scripts/demo_outputs.py compare BEFORE AFTER
    python scripts/demo_outputs.py against REV      # record REV (a git worktree) and this tree, compare

``make demo-compare REV=<commit>`` runs the last form.

``compare`` diffs the two records line by line: CSV bodies and metadata must match exactly, except
the metadata keys listed in ``REWORDED``, at any depth (free-text provenance notes whose wording may change: their
values are text for people, not parameters) and the version line. Figures are not compared (their
pixels depend on the matplotlib build); that a figure was written is.
"""

from __future__ import annotations

import argparse
import difflib
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# metadata keys whose values are wording only (sources, assumptions, notes); compared by presence
REWORDED = (
    "motionsig_version",
    "assumptions",
    "reference",
    "source",
    "sources",
    "note",
    "notes",
    "provenance",
    "radar",
)


def demo_lines(makefile: Path) -> list[str]:
    """The ``motionsig`` command lines of the Makefile's ``demo`` recipe (a leading ``@``, make's "do not
    echo", dropped), make variables left as written."""
    lines, inside = [], False
    for raw in makefile.read_text().splitlines():
        if raw.startswith("demo:"):
            inside = True
            continue
        if inside:
            if not raw.startswith("\t"):
                break
            line = raw.strip().removeprefix("@")
            if line.startswith("$(BIN)/motionsig"):
                lines.append(line)
    return lines


def record(out_dir: Path, root: Path) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    work = out_dir / "out"
    work.mkdir(exist_ok=True)
    shim = out_dir / "bin"
    shim.mkdir(exist_ok=True)
    exe = shim / "motionsig"
    exe.write_text(f'#!/bin/sh\nexec {shlex.quote(sys.executable)} -m motionsig_cli "$@"\n')
    exe.chmod(0o755)
    env = {**os.environ, "PYTHONPATH": str(root), "PATH": f"{shim}:{os.environ['PATH']}"}
    for i, line in enumerate(demo_lines(ROOT / "Makefile")):
        cmd = line.replace("$(BIN)/motionsig", "motionsig").replace("$(OUT)", str(work))
        # run in the checkout: ``python -m`` puts the working directory first on sys.path
        res = subprocess.run(
            ["bash", "-o", "pipefail", "-c", cmd], capture_output=True, text=True, env=env, cwd=root
        )
        name = f"{i:02d}"
        (out_dir / f"{name}.cmd").write_text(line + "\n")
        (out_dir / f"{name}.stdout").write_text(res.stdout)
        (out_dir / f"{name}.rc").write_text(f"{res.returncode}\n")
        for m in re.finditer(r"-o \$\(OUT\)/(\S+)", line):
            src = work / m.group(1)
            (out_dir / f"{name}.{m.group(1)}").write_text(src.read_text() if src.exists() else "(missing)\n")
        for m in re.finditer(r"--plot(?:-compare)? \$\(OUT\)/(\S+)", line):
            (out_dir / f"{name}.fig.{m.group(1)}").write_text(
                "written\n" if (work / m.group(1)).exists() else "missing\n"
            )
        print(f"{name} rc={res.returncode} {line[:100]}", file=sys.stderr)


def _is_note(key: str, value: object) -> bool:
    """A free-text note: a :data:`REWORDED` key holding words (a one-word value such as ``radar: "origin"``
    is a parameter, and is compared)."""
    return key in REWORDED and isinstance(value, str) and " " in value.strip()


def _blank_reworded(value: object) -> object:
    """A metadata value with the text of every :data:`REWORDED` key (at any depth) replaced."""
    if isinstance(value, dict):
        return {k: "(text)" if _is_note(k, v) else _blank_reworded(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_blank_reworded(v) for v in value]
    return value


def _json_or_text(text: str) -> object:
    try:
        return json.loads(text)
    except ValueError:
        return text


def _normalise(text: str) -> list[str]:
    out = []
    for line in text.splitlines():
        m = re.match(r"# ([A-Za-z0-9_]+): (.*)$", line)
        if m and m.group(1) in REWORDED and _is_note(m.group(1), _json_or_text(m.group(2))):
            out.append(f"# {m.group(1)}: (text)")
        elif m and m.group(2).startswith("{"):  # nested metadata (a record's input_meta)
            try:
                value = json.loads(m.group(2))
            except ValueError:
                out.append(line)
                continue
            out.append(f"# {m.group(1)}: {json.dumps(_blank_reworded(value), sort_keys=True)}")
        else:
            out.append(line)
    return out


def compare(before: Path, after: Path) -> int:
    names = sorted(
        {p.name for p in before.iterdir() if p.is_file()} | {p.name for p in after.iterdir() if p.is_file()}
    )
    bad = 0
    for name in names:
        a, b = before / name, after / name
        if not a.exists() or not b.exists():
            print(f"{name}: only in {'after' if b.exists() else 'before'}")
            bad += 1
            continue
        if name.endswith(".cmd"):
            continue
        la, lb = _normalise(a.read_text()), _normalise(b.read_text())
        if la != lb:
            bad += 1
            diff = list(difflib.unified_diff(la, lb, f"before/{name}", f"after/{name}", n=0, lineterm=""))
            print("\n".join(diff[:40]))
    print(f"{len(names)} files compared, {bad} differ")
    return 1 if bad else 0


def against(rev: str) -> int:
    """Record ``rev`` (checked out in a temporary git worktree) and this tree, then compare."""
    with tempfile.TemporaryDirectory(prefix="demo-outputs-") as tmp:
        base = Path(tmp) / "base"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(base), rev], check=True,
                       capture_output=True)  # fmt: skip
        try:
            record(Path(tmp) / "before", base)
            record(Path(tmp) / "after", ROOT)
            return compare(Path(tmp) / "before", Path(tmp) / "after")
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)], check=False)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="what", required=True)
    r = sub.add_parser("record")
    r.add_argument("dir", type=Path)
    r.add_argument("--root", type=Path, default=ROOT)
    c = sub.add_parser("compare")
    c.add_argument("before", type=Path)
    c.add_argument("after", type=Path)
    a = sub.add_parser("against")
    a.add_argument("rev")
    args = p.parse_args()
    if args.what == "record":
        record(args.dir.resolve(), args.root.resolve())
        return 0
    if args.what == "against":
        return against(args.rev)
    return compare(args.before, args.after)


if __name__ == "__main__":
    raise SystemExit(main())
