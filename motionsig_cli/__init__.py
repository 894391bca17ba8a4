"""motionsig: detection and tracking with signatures.

The numerical core (``signals``, and later ``models``, ``filters``, ``detection``,
``surveillance``, ``experiments``) never imports typer, rich or matplotlib; the command
layer lives in :mod:`motionsig_cli.cli` and figures in :mod:`motionsig_cli.plotting`.
"""

__version__ = "0.1.0"
