"""Long runs on the command line (``simulate``, ``transmission``): progress bar, up-front cost
estimate, Ctrl-C/SIGTERM, checkpoints, resume, atomic output and the exit code of a status.

Exit codes (docs/robustness.md): 0 ok; 2 bad input (a geardyn error); 3 the run ended with
status ``diverged``, ``suspect``, ``stopped`` or ``reversed`` (its result is written); 130 the
run was interrupted by Ctrl-C or SIGTERM (the computed part is written with status
``interrupted``).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable
from pathlib import Path

import typer
from rich.markup import escape

from geardyn.cli.common import console
from geardyn.errors import InputError

#: Runs estimated longer than this [s] announce their duration before going on.
LONG_RUN_S = 30.0
EXIT_STATUS = 3
EXIT_INTERRUPTED = 130


def check_run_options(checkpoint_every: float | None) -> None:
    """``--checkpoint-every`` is a finite number of seconds > 0."""
    if checkpoint_every is not None and not (math.isfinite(checkpoint_every)
                                             and checkpoint_every > 0):
        raise InputError(f"--checkpoint-every: must be a finite time > 0 s, got "
                         f"{checkpoint_every:g}")


def _duration(s: float) -> str:
    if s < 120:
        return f"{s:.0f} s"
    if s < 7200:
        return f"{s / 60:.0f} min"
    return f"{s / 3600:.1f} h"


def run_with_control(cfg, out: Path | None, checkpoint_every: float | None,  # noqa: ANN001
                     resume: bool, options: dict, run: Callable, label: str = "simulating"):
    """Call ``run(control)`` under a progress bar with a :class:`RunControl` that stops on
    SIGINT/SIGTERM, writes checkpoints next to ``out`` every ``checkpoint_every`` seconds and,
    with ``resume``, continues from the checkpoint of the same config and ``options``."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    from geardyn.checkpoint import (
        checkpoint_path,
        load_checkpoint,
        run_hash,
        save_checkpoint,
        stop_on_signals,
    )
    from geardyn.solve.control import RunControl

    if (checkpoint_every or resume) and out is None:
        raise InputError("--checkpoint-every/--resume need an output file (the checkpoint is "
                         "written next to it)")
    digest = run_hash(cfg, **options)
    ckpt = checkpoint_path(out) if out is not None else None
    control = RunControl(checkpoint_every_s=checkpoint_every or 0.0)
    if resume:
        control.resume = load_checkpoint(ckpt, digest)
        console.print(f"resuming from {ckpt} (step {int(control.resume['step'])})",
                      highlight=False)
    if checkpoint_every and ckpt is not None:
        control.checkpoint = lambda state: save_checkpoint(ckpt, state, digest)
    with Progress(TextColumn("{task.description}"), BarColumn(),
                  TextColumn("{task.percentage:>5.1f} %"), TimeRemainingColumn(),
                  console=console, transient=True) as prog, stop_on_signals(control):
        task = prog.add_task(label, total=1.0)

        def estimate(seconds: float) -> None:
            if seconds > LONG_RUN_S:
                prog.console.print(f"estimated run time {_duration(seconds)} (measured cost "
                                   "per step × steps); Ctrl-C stops it and keeps the computed "
                                   "part", highlight=False)

        control.progress = lambda f: prog.update(task, completed=f)
        control.estimate = estimate
        return run(control)


def finish_run(ds, out: Path | None, ckpt: Path | None) -> None:  # noqa: ANN001
    """Write ``ds`` atomically to ``out``; a finished run removes its checkpoint."""
    from geardyn.results import to_netcdf

    if out is not None:
        to_netcdf(ds, out)
    if ckpt is not None and ds.attrs.get("status") != "interrupted":
        with contextlib.suppress(FileNotFoundError):
            ckpt.unlink()


def exit_for_status(ds, ckpt: Path | None = None) -> None:  # noqa: ANN001
    """Exit 130 for an interrupted run, 3 for any other status than ``ok``."""
    status = str(ds.attrs.get("status", "ok"))
    if status == "interrupted":
        more = (f"; continue with --resume (checkpoint {ckpt})"
                if ckpt is not None and ckpt.exists() else "")
        console.print(f"[bold yellow]interrupted:[/] {escape(str(ds.attrs['diagnosis']))}{more}",
                      highlight=False)
        raise typer.Exit(code=EXIT_INTERRUPTED)
    if status != "ok":
        console.print(f"[bold yellow]status {status}:[/] {escape(str(ds.attrs['diagnosis']))}",
                      highlight=False)
        raise typer.Exit(code=EXIT_STATUS)
