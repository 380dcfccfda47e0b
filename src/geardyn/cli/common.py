"""Helpers shared by CLI commands: error reporting and ``LINK=VALUE`` parsing."""

from __future__ import annotations

import functools
import math
import os
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

import click
import typer
from rich.console import Console
from rich.markup import escape

from geardyn.errors import GeardynError, InputError

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
        except (typer.Exit, typer.Abort, typer.TyperException, click.exceptions.ClickException):
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
    """Parse ``NAME=SPEED`` items (e.g. ``--input motor=1498.5``, rpm, or with a unit:
    ``motor=25Hz``); non-finite speeds and speeds over 1e6 rpm are refused."""
    out: dict[str, float] = {}
    for item in items or []:
        if "=" not in item:
            raise typer.BadParameter(f"{what} '{item}': expected NAME=NUMBER, e.g. motor=1500")
        name, _, value = item.partition("=")
        try:
            number = float(value)
        except ValueError:
            from geardyn.config.units import to_unit

            try:
                number = to_unit(value, "rpm", "a rotational speed")
            except ValueError as exc:
                raise typer.BadParameter(f"{what} '{item}': {exc}") from None
        if not math.isfinite(number):
            raise typer.BadParameter(f"{what} '{item}': must be a finite number")
        if abs(number) > 1e6:
            raise typer.BadParameter(f"{what} '{item}': {number:g} rpm is implausible "
                                     "(limit 1e6 rpm)")
        out[name.strip()] = number
    return out


def check_output_file(path: Path, option: str) -> None:
    """Refuse, before any work, an output file that cannot be written: a missing or read-only
    directory, or a path that is a directory."""
    if path.is_dir():
        raise InputError(f"{option}: '{path}' is a directory, expected a file name")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{option}: directory '{parent}' does not exist")
    if not os.access(parent, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise InputError(f"{option}: '{path}' is not writable")


def renamed_option(value, old_value, name: str, old_name: str):  # noqa: ANN001, ANN201
    """One CLI grammar (``--out`` for every output): an old option name kept as a hidden alias.
    Returns ``(value, name typed)``; the old name prints a deprecation note, both together are
    refused."""
    if old_value is None:
        return value, name
    if value is not None:
        raise InputError(f"{old_name}: deprecated name of {name}; give only {name}")
    console.print(f"[yellow]note:[/] {old_name} is deprecated; use {name}", highlight=False)
    return old_value, old_name


#: Suffixes of the files a report folder holds (figures, tables, data, reports): a folder of
#: only these may be replaced whole with --force.
REPORT_SUFFIXES = (".png", ".svg", ".pdf", ".csv", ".nc", ".json", ".html", ".txt")


def check_report_dir(path: Path, option: str, force: bool) -> None:
    """One overwrite policy for an output folder, checked before any work: a new or empty
    folder is written; a folder with files is replaced whole only with ``--force`` (so no stale
    figure of an earlier run stays), and only when it holds nothing but report files
    (:data:`REPORT_SUFFIXES`, no sub-folders): ``--force`` never deletes other data."""
    check_output_dir(path, option)
    if not path.is_dir():
        return
    entries = list(path.iterdir())
    if not entries:
        return
    if not force:
        raise InputError(f"{option}: folder '{path}' exists and is not empty; pass --force to "
                         "replace it (its files are removed) or choose another folder")
    here = Path.cwd().resolve()
    if path.resolve() in (here, *here.parents):
        raise InputError(f"{option}: '{path}' is the working folder (or holds it); it cannot "
                         "be replaced: choose a sub-folder, e.g. report/")
    other = [e.name for e in entries if e.is_dir() or e.suffix.lower() not in REPORT_SUFFIXES]
    if other:
        raise InputError(f"{option}: folder '{path}' holds files that are not a report "
                         f"({', '.join(sorted(other)[:3])}); --force replaces only report "
                         "folders: choose a new folder")


@contextmanager
def report_folder(path: Path) -> Iterator[Path]:
    """Write an output folder whole or not at all: yields a temporary sibling folder; on
    success it takes the place of ``path`` (an earlier folder is removed: no stale files),
    on an error or Ctrl-C it is deleted and ``path`` is untouched."""
    import shutil
    import tempfile

    parent = path.parent if str(path.parent) else Path(".")
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".partial", dir=parent))
    mask = os.umask(0)
    os.umask(mask)
    tmp.chmod(0o777 & ~mask)
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    old = None
    if path.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".old", dir=parent))
        old.rmdir()
        path.rename(old)
    tmp.rename(path)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def check_output_dir(path: Path, option: str) -> None:
    """Refuse, before any work, an output directory that cannot be created or written."""
    if path.exists():
        if not path.is_dir():
            raise InputError(f"{option}: '{path}' exists and is not a directory")
        if not os.access(path, os.W_OK):
            raise InputError(f"{option}: directory '{path}' is not writable")
        return
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{option}: parent directory '{parent}' does not exist")
    if not os.access(parent, os.W_OK):
        raise InputError(f"{option}: cannot create '{path}' (parent not writable)")


def check_number(value: float | None, option: str, *, gt: float | None = None,
                 ge: float | None = None, le: float | None = None, unit: str = "") -> None:
    """A CLI number: finite and within its range, else an InputError naming the option."""
    if value is None:
        return
    u = f" {unit}" if unit else ""
    if not math.isfinite(value):
        raise InputError(f"{option}: must be a finite number, got {value}")
    if gt is not None and not value > gt:
        raise InputError(f"{option}: must be > {gt:g}{u}, got {value:g}")
    if ge is not None and not value >= ge:
        raise InputError(f"{option}: must be ≥ {ge:g}{u}, got {value:g}")
    if le is not None and not value <= le:
        raise InputError(f"{option}: must be ≤ {le:g}{u}, got {value:g}")


#: Protocols of a dask.distributed scheduler address.
SCHEDULER_PROTOCOLS = ("tcp", "tls", "ws", "wss", "ucx")


def check_scheduler(address: str, option: str = "--scheduler", timeout_s: float = 5.0) -> None:
    """A dask scheduler address ``PROTOCOL://HOST:PORT`` (protocol tcp by default) that
    accepts a connection within ``timeout_s``; else an InputError naming ``option``, before
    any work (dask would fail later with an internal error or wait 30 s)."""
    import socket
    from urllib.parse import urlsplit

    text = address.strip()
    parts = urlsplit(text if "://" in text else f"tcp://{text}")
    example = "e.g. tcp://10.0.0.1:8786"
    if parts.scheme not in SCHEDULER_PROTOCOLS:
        raise InputError(f"{option}: unknown protocol '{parts.scheme}' in {address!r} (one of "
                         f"{', '.join(SCHEDULER_PROTOCOLS)}; {example})")
    try:
        host, port = parts.hostname, parts.port
    except ValueError:
        raise InputError(f"{option}: {address!r} has no valid port (0-65535; {example})"
                         ) from None
    if not host or port is None or " " in text or parts.path not in ("", "/"):
        raise InputError(f"{option}: {address!r} is not a scheduler address HOST:PORT "
                         f"({example})")
    try:
        with socket.create_connection((host, port), timeout=timeout_s):
            pass
    except OSError as exc:
        raise InputError(f"{option}: cannot connect to the scheduler at {address!r} "
                         f"({exc.strerror or exc}); is it running?") from None
