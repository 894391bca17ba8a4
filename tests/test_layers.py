"""Layering: the numerical core imports neither typer, rich nor matplotlib."""

import subprocess
import sys

CORE = [
    "motionsig_cli.signals.gf2",
    "motionsig_cli.signals.lfsr",
    "motionsig_cli.signals.gold",
    "motionsig_cli.signals.gps",
    "motionsig_cli.signals.modes",
    "motionsig_cli.signals.signature",
    "motionsig_cli.signals.correlation",
    "motionsig_cli.tables",
    "motionsig_cli.rng",
    "motionsig_cli.engine",
    "motionsig_cli.detection.lmp_fft",
    "motionsig_cli.refdata",
    "motionsig_cli.models.vehicle",
    "motionsig_cli.filters.kalman",
    "motionsig_cli.detection.lmp",
    "motionsig_cli.experiments.lmp1d",
    "motionsig_cli.surveillance.jamming",
    "motionsig_cli.surveillance.antenna",
    "motionsig_cli.experiments.jamming",
    "motionsig_cli.surveillance.multilateration",
    "motionsig_cli.surveillance.clock",
    "motionsig_cli.surveillance.clock_tracking",
    "motionsig_cli.experiments.satellite_tracking",
    "motionsig_cli.models.vehicle2d",
    "motionsig_cli.filters.unscented",
    "motionsig_cli.experiments.lmp2d",
    "motionsig_cli.models.motion",
    "motionsig_cli.filters.imm",
    "motionsig_cli.detection.glr",
    "motionsig_cli.experiments.maneuver",
    "motionsig_cli.surveillance.amplitude",
    "motionsig_cli.surveillance.multiple_access",
    "motionsig_cli.surveillance.roc_bounds",
    "motionsig_cli.surveillance.roc_exact",
    "motionsig_cli.surveillance.gaussian_roc",
    "motionsig_cli.surveillance.quasi_optimal",
    "motionsig_cli.surveillance.time_bandwidth",
    "motionsig_cli.surveillance.psk_amplitude",
    "motionsig_cli.experiments.mac_roc",
]


def test_core_imports_no_ui_or_plotting():
    code = (
        "import sys\n"
        + "".join(f"import {m}\n" for m in CORE)
        + "bad = [m for m in ('typer', 'rich', 'matplotlib', 'motionsig_cli.cli') if m in sys.modules]\n"
        + "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
