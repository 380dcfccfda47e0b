"""Helpers shared by CLI commands: error reporting and ``LINK=VALUE`` parsing."""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable
from typing import Any, TypeVar

import click
import typer
from rich.console import Console
from rich.markup import escape

from geardyn.errors import GeardynError

# Tables are wide: when output is not a terminal (pipes, files, CI logs) do not wrap at 80.
_WIDTH = None if sys.stdout.isatty() or os.environ.get("COLUMNS") else 200
console = Console(width=_WIDTH)
err_console = Console(stderr=True, width=_WIDTH)

F = TypeVar("F", bound=Callable[..., Any])


#: Set by ``geardyn --debug`` (or the environment variable GEARDYN_DEBUG=1): unexpected
#: errors show their traceback instead of one line.
DEBUG = {"on": bool(os.environ.get("GEARDYN_DEBUG"))}


def friendly_errors(func: F) -> F:
    """Print geardyn errors as a message (no traceback) and exit with code 2; any other
    exception (a bug) as one line naming it and exit code 1 — ``--debug`` shows the traceback;
    Ctrl-C ends with exit code 130 and no traceback."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except GeardynError as exc:
            err_console.print(
                f"[bold red]error:[/] {escape(str(exc))}", highlight=False, soft_wrap=True
            )
            raise typer.Exit(code=2) from None
        except (typer.Exit, typer.Abort, click.exceptions.ClickException):
            raise
        except KeyboardInterrupt:
            err_console.print("[bold yellow]interrupted[/]", highlight=False)
            raise typer.Exit(code=130) from None
        except Exception as exc:  # noqa: BLE001 - last-resort handler: one clear line
            if DEBUG["on"]:
                raise
            err_console.print(
                f"[bold red]internal error:[/] {escape(type(exc).__name__)}: "
                f"{escape(str(exc))} (run with --debug for the traceback)",
                highlight=False, soft_wrap=True,
            )
            raise typer.Exit(code=1) from None

    return wrapper  # type: ignore[return-value]


def parse_assignments(items: list[str] | None, what: str = "input") -> dict[str, float]:
    """Parse ``NAME=NUMBER`` items (e.g. ``--input motor=1498.5``)."""
    out: dict[str, float] = {}
    for item in items or []:
        if "=" not in item:
            raise typer.BadParameter(f"{what} '{item}': expected NAME=NUMBER, e.g. motor=1500")
        name, _, value = item.partition("=")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            raise typer.BadParameter(f"{what} '{item}': '{value}' is not a number") from None
    return out
