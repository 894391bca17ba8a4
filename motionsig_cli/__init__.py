"""motionsig: detection and tracking with signatures.

Floors, each importing only those below it: the command layer :mod:`motionsig_cli.cli` (parsing, I/O,
progress) and :mod:`motionsig_cli.plotting` → one package per source system (``modesig``, ``existence``,
``maneuver``, ``atc10``: studies, Monte Carlo jobs, pipelines over a user's records; no system imports
another) → ``detection``, ``filters`` and ``surveillance`` (estimators, detectors, the ATC-10
mathematics) → ``signals`` and ``models`` → records, geodesy, tables, the engine, configuration. Below the
command layer nothing imports typer, rich or matplotlib. A bad parameter is a
:class:`motionsig_cli.config.ConfigError` naming its field; every Monte Carlo is a
:class:`motionsig_cli.engine.MonteCarloJob`.

The public Python API is the names in :data:`__all__`, importable from the package itself
(``from motionsig_cli import gold_family``). They are loaded on first use, so that ``import
motionsig_cli`` (and the command line's start-up) stays fast. Within the 0.x releases a public name
keeps its meaning and the arguments it accepts; new keyword arguments with defaults may be added.
Everything else — the modules' other functions, the studies behind the commands, the command layer — is internal and
may change in any release.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

# public name -> module that defines it
_PUBLIC: dict[str, str] = {
    # spreading codes and signatures
    "m_sequence": "motionsig_cli.signals.lfsr",
    "preferred_pairs": "motionsig_cli.signals.gold",
    "gold_code": "motionsig_cli.signals.gold",
    "gold_family": "motionsig_cli.signals.gold",
    "ca_code": "motionsig_cli.signals.gps",
    "ca_codes": "motionsig_cli.signals.gps",
    "periodic_correlation": "motionsig_cli.signals.correlation",
    "parse_codes": "motionsig_cli.signals.code_spec",
    "mode_signature": "motionsig_cli.signals.signature",
    # vehicle models
    "Vehicle1D": "motionsig_cli.models.vehicle",
    "simulate_1d": "motionsig_cli.models.vehicle",
    "Vehicle2D": "motionsig_cli.models.vehicle2d",
    "simulate_2d": "motionsig_cli.models.vehicle2d",
    # the LMP mode detector
    "LMPConfig": "motionsig_cli.detection.lmp",
    "RadarLMPConfig": "motionsig_cli.detection.lmp",
    "LMPResult": "motionsig_cli.detection.lmp",
    "lmp_detect": "motionsig_cli.detection.lmp",
    "lmp_detect_radar": "motionsig_cli.detection.lmp",
    "lmp_detect_fft": "motionsig_cli.detection.lmp_fft",
    "ModeDetection": "motionsig_cli.modesig.array_record",
    "detect_mode": "motionsig_cli.modesig.array_record",
    "detect_mode_radar": "motionsig_cli.modesig.array_record",
    # filters and tests
    "imm_filter": "motionsig_cli.filters.imm",
    "ModelSet": "motionsig_cli.models.motion",
    "imm_models": "motionsig_cli.models.motion",
    "two_point_init": "motionsig_cli.models.motion",
    "wald_thresholds": "motionsig_cli.detection.sprt",
    # the manoeuvre trackers on a track
    "TrackerConfig": "motionsig_cli.maneuver.study",
    "TrackResult": "motionsig_cli.maneuver.tracking",
    "track_positions": "motionsig_cli.maneuver.tracking",
    # track existence (SLRT)
    "Sensor": "motionsig_cli.existence.detection_scoring",
    "ExistenceScores": "motionsig_cli.existence.detection_scoring",
    "score_detections": "motionsig_cli.existence.detection_scoring",
    "SlrtRecordConfig": "motionsig_cli.existence.slrt_record",
    # multilateration
    "EpochFix": "motionsig_cli.atc10.epoch_fix",
    "solve_epoch": "motionsig_cli.atc10.epoch_fix",
    # records, Monte Carlo, errors
    "read_record": "motionsig_cli.records",
    "RecordSpec": "motionsig_cli.records",
    "Role": "motionsig_cli.records",
    "Engine": "motionsig_cli.engine",
    "MonteCarloJob": "motionsig_cli.engine",
    "run_job": "motionsig_cli.engine",
    "trial_rng": "motionsig_cli.rng",
    "ConfigError": "motionsig_cli.config",
    "InputError": "motionsig_cli.errors",
}

__all__ = ["__version__", *_PUBLIC]


def __getattr__(name: str) -> Any:
    """Load a public name from its module on first use (PEP 562)."""
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'motionsig_cli' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC))
