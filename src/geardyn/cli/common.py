"""Helpers shared by CLI commands: error reporting and ``LINK=VALUE`` parsing."""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable
from typing import Any, TypeVar

import typer
from rich.console import Console
from rich.markup import escape

from geardyn.errors import GeardynError

# Tables are wide: when output is not a terminal (pipes, files, CI logs) do not wrap at 80.
_WIDTH = None if sys.stdout.isatty() or os.environ.get("COLUMNS") else 200
console = Console(width=_WIDTH)
err_console = Console(stderr=True, width=_WIDTH)

F = TypeVar("F", bound=Callable[..., Any])


def friendly_errors(func: F) -> F:
    """Print geardyn errors as a message (no traceback) and exit with code 2."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except GeardynError as exc:
            err_console.print(
                f"[bold red]error:[/] {escape(str(exc))}", highlight=False, soft_wrap=True
            )
            raise typer.Exit(code=2) from None

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
