"""`motionsig encode` (placeholder while the core is written)."""

import typer

app = typer.Typer(help="Gold codes, m-sequences, GPS C/A codes and mode signatures.", no_args_is_help=True)


@app.command()
def mseq(poly: str = typer.Option("45", help="Primitive polynomial.")) -> None:
    """Placeholder."""
    typer.echo(poly)
