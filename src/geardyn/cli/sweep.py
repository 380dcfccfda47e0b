"""``geardyn sweep SPEC.toml --out DATASET.zarr``: run a parameter sweep on dask.distributed
into one Zarr store (docs/sweeps.md). Re-running the same command resumes: finished cases whose
data match their checksums are skipped, damaged ones run again. Exit codes: 0 every case
stored and none ``failed``; 1 some case ``failed`` (the count is printed) or, with
``--verify``, some case damaged; 2 a bad spec or option, a failing run-time check, or a store
in use by another driver; 130 Ctrl-C (the store keeps every finished case)."""

from __future__ import annotations

import warnings
from pathlib import Path

import typer

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors


def _rate(p) -> str:  # noqa: ANN001 - SweepProgress
    r = p.rate_per_min
    eta = p.eta_s
    rate = f"{r:.3g} cases/min" if r == r else "– cases/min"
    if eta != eta:
        return f"{rate}, ETA –"
    m, s = divmod(int(round(eta)), 60)
    h, m = divmod(m, 60)
    return f"{rate}, ETA {h:d}:{m:02d}:{s:02d}"


@app.command("sweep")
@friendly_errors
def sweep_cmd(
    spec: Path = typer.Argument(..., help="sweep spec (TOML: \\[sweep], \\[\\[axes]], "
                                "\\[outputs])"),
    out: Path = typer.Option(..., "--out", "-o", help="Zarr store (created, or resumed)"),
    scheduler: str | None = typer.Option(
        None, "--scheduler", help="address of a running dask scheduler, e.g. "
        "tcp://10.0.0.1:8786 (default: a LocalCluster on this machine)"),
    workers: int | None = typer.Option(
        None, "--workers", "-n", help="LocalCluster worker processes (default: one per core)"),
    retry_failed: bool = typer.Option(False, "--retry-failed",
                                      help="run the cases stored as 'failed' again"),
    check: bool = typer.Option(False, "--check", help="validate the spec and every case, "
                               "run the run-time checks (time step, channel kinds, run length "
                               "against the diagnosis statistics), run nothing"),
    verify: bool = typer.Option(False, "--verify", help="check every stored case against its "
                                "checksum, name the damaged ones, run nothing"),
) -> None:
    """Run every case of a sweep spec (axes over config paths) and store channels,
    indicators, states and verdicts per case in one Zarr data set."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from geardyn.errors import InputError
    from geardyn.sweep import load_spec, run

    if workers is not None and workers < 1:
        raise InputError(f"--workers: must be ≥ 1, got {workers}")
    if workers is not None and scheduler is not None:
        raise InputError("--workers applies to the LocalCluster; with --scheduler the cluster "
                         "has its own workers")
    from geardyn.cli.common import check_output_dir, check_scheduler

    check_output_dir(out, "--out")
    sweep = load_spec(spec)
    if scheduler is not None and not check:
        check_scheduler(scheduler)
    axes = ", ".join(f"{a.name} ({len(a.values)})" for a in sweep.axes)
    from rich.markup import escape

    console.print(escape(f"sweep {sweep.spec.sweep.name or spec.name}: {len(sweep.cases)} "
                         f"cases [{axes}; {sweep.spec.sweep.combine}, "
                         f"{sweep.spec.sweep.replicates} replicate(s)]"), highlight=False)
    if verify:
        _verify(out, sweep)
        return
    if check:
        _check(sweep)
        return
    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.fields[rate]}"),
                  TimeElapsedColumn(), console=console, transient=True) as prog:
        task = prog.add_task("starting", total=len(sweep.cases), rate="")

        def progress(p) -> None:  # noqa: ANN001 - SweepProgress
            prog.update(task, completed=p.skipped + p.done,
                        description=f"done {p.skipped + p.done} (failed {p.failed}) / left "
                        f"{p.left}", rate=_rate(p))

        try:
            with warnings.catch_warnings():
                warnings.simplefilter("always")
                warnings.showwarning = _show_warning
                summary = run(sweep, out, scheduler=scheduler, n_workers=workers,
                              retry_failed=retry_failed, progress=progress)
        except KeyboardInterrupt:
            prog.stop()
            if out.exists():
                from geardyn.sweep.store import statuses

                n = int((statuses(out) != "").sum())
                console.print(f"{out}: {n} of {len(sweep.cases)} cases stored; run the same "
                              "command again to finish the sweep", highlight=False)
            raise
    from geardyn.sweep.store import statuses

    status = statuses(out)
    counts = {s: int((status == s).sum()) for s in sorted(set(status)) if s}
    for i, why in sorted(summary.damaged.items()):
        console.print(f"case {i} was damaged ({why}): run again", highlight=False)
    console.print(f"wrote {out}: {summary.run} case(s) run now, {summary.skipped} already "
                  f"stored, {summary.wall_s:.1f} s; status "
                  + ", ".join(f"{k} {v}" for k, v in counts.items()), highlight=False)
    if summary.failed_total:
        console.print(f"{summary.failed_total} of {summary.total} case(s) failed (see the "
                      "store's 'message'); --retry-failed runs them again", highlight=False)
        raise typer.Exit(1)


def _show_warning(message, category, *args, **kwargs) -> None:  # noqa: ANN001, ANN002, ANN003, ARG001
    """A warning during the run as one line (no source line), e.g. a stale lock taken over."""
    from rich.markup import escape

    console.print(f"[bold yellow]warning:[/] {escape(str(message))}", highlight=False)


def _check(sweep) -> None:  # noqa: ANN001 - Sweep
    """Run-time checks of every case (ConfigError → exit 2) and cases too short to judge."""
    from rich.markup import escape

    from geardyn.sweep.layout import plan
    from geardyn.sweep.verdicts import planet_row_notes, short_case_notes

    layout = plan(sweep)
    for note in layout.notes:
        console.print(f"warning: {note}", highlight=False)
    for note in [*short_case_notes(sweep), *planet_row_notes(sweep)]:
        console.print(f"warning: {escape(note)}", highlight=False)
    console.print("spec, every case and the run-time checks are valid; nothing run (--check)")


def _verify(out: Path, sweep) -> None:  # noqa: ANN001 - Sweep
    from geardyn.errors import InputError
    from geardyn.sweep.store import PENDING, check_same_sweep, statuses, verify

    if not out.exists():
        raise InputError(f"--out: store '{out}' does not exist (nothing to verify)")
    check_same_sweep(out, sweep)
    damaged = verify(out)
    status = statuses(out)
    done = int((status != PENDING).sum())
    for i, why in sorted(damaged.items()):
        console.print(f"case {i}: {why}", highlight=False)
    if damaged:
        console.print(f"{len(damaged)} of {done} stored case(s) damaged: run the same command "
                      "without --verify to run them again", highlight=False)
        raise typer.Exit(1)
    console.print(f"{out}: {done} stored case(s) match their checksums "
                  f"({len(status) - done} pending)", highlight=False)
