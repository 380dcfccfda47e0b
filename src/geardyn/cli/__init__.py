"""Command-line interface: ``geardyn kinematics|stiffness|modes|simulate|transmission|analyze|
diagnose|demo``.

Each command lives in its own module and registers itself on :data:`app`; the CLI only calls
the public Python API. Errors from geardyn are printed as one clear message (exit code 2).
"""

from __future__ import annotations

import typer

app = typer.Typer(
    name="geardyn",
    help="Dynamics and condition monitoring of gear transmissions.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)



def _version(value: bool) -> None:
    if value:
        from geardyn import __version__

        typer.echo(f"geardyn {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    debug: bool = typer.Option(False, "--debug", help="show tracebacks of unexpected errors"),
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="print the version and exit"),
) -> None:
    """Dynamics and condition monitoring of gear transmissions."""
    import os

    from geardyn.cli.common import DEBUG

    DEBUG["on"] = debug or bool(os.environ.get("GEARDYN_DEBUG"))


# Command modules register themselves on import (one line each).
from geardyn.cli import analyze as _analyze  # noqa: E402,F401
from geardyn.cli import demo as _demo  # noqa: E402,F401
from geardyn.cli import diagnose as _diagnose  # noqa: E402,F401
from geardyn.cli import kinematics as _kinematics  # noqa: E402,F401
from geardyn.cli import modes as _modes  # noqa: E402,F401
from geardyn.cli import simulate as _simulate  # noqa: E402,F401
from geardyn.cli import stiffness as _stiffness  # noqa: E402,F401
from geardyn.cli import transmission as _transmission  # noqa: E402,F401

__all__ = ["app"]
