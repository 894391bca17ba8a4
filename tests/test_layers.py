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
    assert len(CORE) > 40 and "motionsig_cli.engine" in CORE and "motionsig_cli.experiments.slrt" in CORE
    code = (
        "import sys\n"
        + "".join(f"import {m}\n" for m in CORE)
        + "bad = [m for m in ('typer', 'rich', 'matplotlib', 'motionsig_cli.cli') if m in sys.modules]\n"
        + "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
