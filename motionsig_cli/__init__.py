"""motionsig: detection and tracking with signatures.

Layers, each importing only those below it: the command layer :mod:`motionsig_cli.cli` (parsing, I/O,
progress) → ``experiments`` (scenarios, Monte Carlo jobs, tables) → ``detection``, ``filters`` and
``surveillance`` (estimators, detectors, the ATC-10 analyses) → ``signals`` and ``models``. Below the
command layer nothing imports typer, rich or matplotlib; figures live in :mod:`motionsig_cli.plotting`.
A bad parameter is a :class:`motionsig_cli.config.ConfigError` naming its field; every Monte Carlo is a
:class:`motionsig_cli.engine.MonteCarloJob`.
"""

__version__ = "0.1.0"
