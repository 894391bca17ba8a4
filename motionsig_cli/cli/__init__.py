"""The command layer: typer commands, option validation, CSV/JSON I/O, progress and plot call sites.

Nothing in the numerical core imports this package.
"""
