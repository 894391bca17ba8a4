"""The console-script entry point: imports the application, so that a Ctrl-C during the imports
(numpy, scipy, matplotlib: about a second) ends quietly with exit code 130 instead of a traceback."""

from __future__ import annotations

import sys


def main() -> int:
    """``motionsig``: import :mod:`motionsig_cli.cli.app` and run it."""
    try:
        from motionsig_cli.cli.app import main as app_main
    except KeyboardInterrupt:
        sys.stderr.write("motionsig: interrupted\n")
        return 130
    return app_main()
