"""``geardyn simulate CONFIG --out run.nc`` — time simulation of the config's dynamic model
(lumped planetary: Newmark/HHT-α; FE transmission: explicit Verlet) measured by its
``[[sensors]]``, with a progress bar; the result is written as NetCDF in the layout of
docs/results.md."""

from __future__ import annotations

import math
from pathlib import Path

import typer
from rich.markup import escape

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors
from geardyn.cli.runs import check_run_options, exit_for_status, finish_run, run_with_control


@app.command("simulate")
@friendly_errors
def simulate_cmd(
    config: Path = typer.Argument(
        ..., help="TOML config with \\[planetary_dynamics.simulation] or \\[transmission]"),
    out: Path = typer.Option(..., "--out", help="output NetCDF file (e.g. run.nc)"),
    t_end: float | None = typer.Option(None, "--t-end", help="override t_end_s (s), planetary"),
    revolutions: float | None = typer.Option(
        None, "--revolutions", help="override the speed-law revolutions, FE transmission"),
    seed: int = typer.Option(0, "--seed", help="seed of every random draw (sensor noise, "
                             "random errors)"),
    force: bool = typer.Option(False, "--force", "--overwrite",
                               help="overwrite an existing --out file"),
    checkpoint_every: float | None = typer.Option(
        None, "--checkpoint-every", help="write the integrator state to OUT.ckpt.npz every "
        "SECONDS of wall-clock time (and on Ctrl-C), for --resume"),
    resume: bool = typer.Option(False, "--resume", help="continue a killed or interrupted run "
                                "from OUT.ckpt.npz (same config and options)"),
) -> None:
    """Simulate run-up/run-down/stationary operation; writes shaft angles and speeds, mesh
    forces, model states and the sensor channels.

    Exit codes: 0 ok; 2 bad input; 3 the run ended diverged, suspect, stopped or reversed
    (result written); 130 interrupted by Ctrl-C/SIGTERM (computed part written with status
    interrupted). See docs/robustness.md."""
    import warnings

    from geardyn.checkpoint import check_output, checkpoint_path
    from geardyn.config import load_config
    from geardyn.errors import InputError
    from geardyn.results import channels

    if t_end is not None and not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"--t-end: must be a finite time > 0 s, got {t_end:g}")
    check_run_options(checkpoint_every)
    check_output(out, "--out", overwrite=force or resume)
    cfg = load_config(config)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = run_with_control(
            cfg, out, checkpoint_every, resume,
            options={"seed": seed, "t_end_s": t_end, "revolutions": revolutions},
            run=lambda ctl: _run(cfg, seed, t_end, revolutions, ctl))
    for w in caught:
        console.print(f"[bold yellow]warning:[/] {escape(str(w.message))}", highlight=False)
    ds.attrs["config"] = str(config)
    finish_run(ds, out, checkpoint_path(out))
    ch = channels(ds)
    console.print(f"wrote {out}: {ds.sizes['time']} samples × {ds.sizes['shaft']} shafts, "
                  f"{len(ch)} sensor channel(s){': ' + ', '.join(ch) if ch else ''}")
    exit_for_status(ds, checkpoint_path(out))


def _run(cfg, seed: int, t_end: float | None, revolutions: float | None,  # noqa: ANN001
         control):  # noqa: ANN001, ANN202
    from geardyn.run import run_simulation

    return run_simulation(cfg, seed=seed, t_end_s=t_end, revolutions=revolutions,
                          control=control)
