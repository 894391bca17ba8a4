"""The architecture check of the package (issue: "A house for 50,000 lines").

Reads the package's source (nothing is imported) and reports:

- each top-level folder's share of the package's lines (no folder may hold more than 20 %);
- the module import graph, every ``import`` statement counted wherever it stands (module level, inside a
  function, under ``if TYPE_CHECKING``), its cycles, and every import that points up the layers below;
- the length of every command function of the command layer, its decorators and declarations included
  (at most 100 lines);
- with ``--startup``, the start-up time of ``motionsig --help`` against ``import numpy, typer``.

``python scripts/architecture.py`` prints the report and exits 1 if a rule is broken; ``tests/test_layers.py``
asserts the same rules.
"""

from __future__ import annotations

import ast
import subprocess
import sys
import time
from collections.abc import Iterable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "motionsig_cli"
NAME = "motionsig_cli"

# The floors, lowest first. A module may import modules of its own floor or below, never above; the
# system packages (floor 3) may not import one another: what two systems share moves down a floor.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("errors", "config", "rng", "roots", "cache", "refdata", "tables", "records", "geodesy", "engine", "taskdata", "checkpoint_key"),
    ("signals", "models"),
    ("surveillance", "filters", "detection"),
    ("modesig", "existence", "maneuver", "atc10"),
    ("plotting",),
    ("cli", "__main__"),
)
SYSTEMS = LAYERS[3]
MAX_FOLDER_SHARE = 0.20
MAX_COMMAND_LINES = 100
MAX_STARTUP_RATIO = 2.5


def module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    return ".".join(rel.parts).removesuffix(".__init__")


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _targets(mod: str, path: Path, node: ast.Import | ast.ImportFrom, known: Iterable[str]) -> list[str]:
    known = set(known)
    if isinstance(node, ast.Import):
        names = [a.name for a in node.names]
    else:
        base = node.module or ""
        if node.level:
            parts = mod.split(".")
            keep = len(parts) - node.level + (1 if path.name == "__init__.py" else 0)
            base = ".".join(parts[:keep] + ([base] if base else []))
        names = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base for a in node.names]
    out = []
    for name in names:
        while name and name not in known and "." in name:
            name = name.rsplit(".", 1)[0]
        if name in known and name != mod:
            out.append(name)
    return out


def import_graph() -> dict[str, set[str]]:
    """module -> the package's modules it imports, every import statement counted (lazy ones too)."""
    mods = modules()
    graph: dict[str, set[str]] = {}
    for mod, path in mods.items():
        edges: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import | ast.ImportFrom):
                edges.update(_targets(mod, path, node, mods))
        # a module's own package __init__ is run by importing it: not an edge of the code's design
        graph[mod] = {t for t in edges if not mod.startswith(t + ".")}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each a cycle or a knot of them."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10_000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def room(mod: str) -> str:
    """The top-level folder or module of a module: ``motionsig_cli.maneuver.study`` -> ``maneuver``."""
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def floor(mod: str) -> int | None:
    r = room(mod)
    for i, rooms in enumerate(LAYERS):
        if r in rooms:
            return i
    return None


def layer_violations(graph: dict[str, set[str]]) -> list[str]:
    """Imports that point up a floor, cross from one system to another, or leave a module of no floor."""
    bad = []
    for mod, targets in sorted(graph.items()):
        if mod == NAME:
            continue
        f = floor(mod)
        if f is None:
            bad.append(f"{mod}: in no floor of LAYERS")
            continue
        for t in sorted(targets):
            g = floor(t)
            if t == NAME:
                continue
            if g is None or g > f:
                bad.append(f"{mod} -> {t}: imports up, floor {f} -> {g}")
            elif f == g == 3 and room(mod) != room(t):
                bad.append(f"{mod} -> {t}: one system imports another")
    return bad


def lines(path: Path) -> int:
    return len(path.read_text().splitlines())


def folder_shares() -> dict[str, float]:
    """Each top-level folder's share of the package's lines (top-level modules count one by one)."""
    total = 0
    per: dict[str, int] = {}
    for p in PACKAGE.rglob("*.py"):
        n = lines(p)
        total += n
        key = p.relative_to(PACKAGE).parts[0]
        per[key] = per.get(key, 0) + n
    return {k: v / total for k, v in sorted(per.items(), key=lambda kv: -kv[1])} | {"(total lines)": total}


def command_lengths() -> dict[str, int]:
    """Every command function of ``cli/`` (a function decorated with something named ``command``) and its
    length in lines from its first decorator to its last line."""
    out = {}
    for p in sorted((PACKAGE / "cli").glob("*.py")):
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, ast.FunctionDef) and any(
                "command" in ast.unparse(d) for d in node.decorator_list
            ):
                start = min([d.lineno for d in node.decorator_list] + [node.lineno])
                out[f"{p.name}:{node.name}"] = node.end_lineno - start + 1
    return out


def startup_ratio(repeats: int = 7) -> tuple[float, float, float]:
    """Median wall time of ``motionsig --help`` and of ``import numpy, typer`` in fresh interpreters."""

    def median(cmd: list[str]) -> float:
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            subprocess.run(cmd, capture_output=True, check=True)
            times.append(time.perf_counter() - t0)
        return sorted(times)[len(times) // 2]

    cli = median([sys.executable, "-m", NAME, "--help"])
    base = median([sys.executable, "-c", "import numpy, typer"])
    return cli, base, cli / base


def main(argv: list[str]) -> int:
    graph = import_graph()
    shares = folder_shares()
    total = shares.pop("(total lines)")
    print(f"package: {int(total)} lines in {len(graph)} modules")
    failed = False
    for k, v in shares.items():
        flag = "  <-- over 20 %" if v > MAX_FOLDER_SHARE else ""
        failed |= bool(flag)
        print(f"  {k:<16} {v:6.1%}{flag}")
    cyc = cycles(graph)
    print(f"import cycles (lazy imports included): {len(cyc)}")
    for c in cyc:
        print("  " + " <-> ".join(m.removeprefix(NAME + ".") for m in c))
    bad = layer_violations(graph)
    print(f"imports against the layers: {len(bad)}")
    for b in bad:
        print("  " + b)
    lengths = command_lengths()
    long = {k: v for k, v in lengths.items() if v > MAX_COMMAND_LINES}
    print(f"command functions: {len(lengths)}, longest {max(lengths.values())} lines, over {MAX_COMMAND_LINES}: {len(long)}")
    for k, v in sorted(long.items(), key=lambda kv: -kv[1]):
        print(f"  {k}: {v}")
    failed |= bool(cyc or bad or long)
    if "--startup" in argv:
        cli, base, ratio = startup_ratio()
        print(f"start-up: motionsig --help {cli * 1e3:.0f} ms, import numpy, typer {base * 1e3:.0f} ms: {ratio:.2f}x")
        failed |= ratio > MAX_STARTUP_RATIO
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
