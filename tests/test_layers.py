"""Layering: the numerical core imports neither typer, rich nor matplotlib."""

import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "motionsig_cli"
# every module of the package but the command layer and the plotting module
CORE = sorted(
    "motionsig_cli." + ".".join(p.relative_to(PACKAGE).with_suffix("").parts).removesuffix(".__init__")
    for p in PACKAGE.rglob("*.py")
    if p.relative_to(PACKAGE).parts[0] not in ("cli", "plotting.py", "__main__.py")
)


def test_core_imports_no_ui_or_plotting():
    assert len(CORE) > 40 and "motionsig_cli.engine" in CORE and "motionsig_cli.existence.slrt" in CORE
    code = (
        "import sys\n"
        + "".join(f"import {m}\n" for m in CORE)
        + "bad = [m for m in ('typer', 'rich', 'matplotlib', 'motionsig_cli.cli') if m in sys.modules]\n"
        + "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


# --- the house (scripts/architecture.py): folders, cycles, floors, thin commands -----------------------

def _architecture():
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "scripts" / "architecture.py"
    spec = importlib.util.spec_from_file_location("architecture", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


ARCH = _architecture()


def test_no_folder_holds_more_than_a_fifth_of_the_package():
    shares = ARCH.folder_shares()
    total = shares.pop("(total lines)")
    assert total > 30_000
    assert max(shares.values()) <= ARCH.MAX_FOLDER_SHARE, shares


def test_no_import_cycle_lazy_imports_included():
    graph = ARCH.import_graph()
    # the graph sees imports inside functions and under TYPE_CHECKING: the command layer imports the
    # systems only inside its functions, and those edges are there
    assert "motionsig_cli.maneuver.study" in graph["motionsig_cli.cli.maneuver"]
    assert ARCH.cycles(graph) == []


def test_the_cycle_finder_finds_cycles():
    # a planted cycle of three and one of two beside an acyclic part: the check can fail
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"e"}, "e": {"d", "a"}, "f": {"a"}}
    assert sorted(ARCH.cycles(graph)) == [["a", "b", "c"], ["d", "e"]]


def test_imports_point_down_and_systems_do_not_import_one_another():
    assert ARCH.layer_violations(ARCH.import_graph()) == []
    # the rule is live: an import up a floor and one across systems are both reported
    planted = {
        "motionsig_cli.filters.kalman": {"motionsig_cli.maneuver.study"},
        "motionsig_cli.maneuver.study": {"motionsig_cli.atc10.toa_solve", "motionsig_cli.filters.imm"},
    }
    bad = ARCH.layer_violations(planted)
    assert len(bad) == 2 and "imports up" in bad[0] and "one system imports another" in bad[1]


def test_every_module_has_a_floor():
    assert all(ARCH.floor(m) is not None for m in ARCH.modules() if m != "motionsig_cli")


def test_command_functions_are_thin():
    lengths = ARCH.command_lengths()
    assert len(lengths) >= 30
    long = {k: v for k, v in lengths.items() if v > ARCH.MAX_COMMAND_LINES}
    assert long == {}
