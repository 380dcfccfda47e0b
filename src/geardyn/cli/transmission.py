"""``geardyn transmission CONFIG``: alias of ``geardyn simulate`` for the FE transmission
(Thibault et al. 2024), with its linearised modes (and optionally a Campbell table) printed
first. The run is the same code as ``simulate`` (:func:`geardyn.cli.simulate.run_and_write`)."""

from __future__ import annotations

import math
from pathlib import Path

import typer
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors, renamed_option
from geardyn.config import load_config
from geardyn.errors import ConfigError, InputError


def parse_campbell(spec: str | None):  # noqa: ANN201 - (speeds, unit) or (None, None)
    """``--campbell`` of ``transmission``: the range syntax of ``geardyn modes``
    (:func:`geardyn.cli.modes.parse_speeds`). A bare number, the old form (top speed in rpm,
    five speeds from 0), still works with a deprecation note."""
    if spec is None:
        return None, None
    import numpy as np

    from geardyn.cli.modes import parse_speeds

    try:
        top = float(spec)
    except ValueError:
        return parse_speeds(spec)
    if not (math.isfinite(top) and top > 0):
        raise InputError(f"--campbell: the top speed must be a finite number > 0 rpm, got "
                         f"{spec!r}; the range form is e.g. \"0:3000:7 rpm\"")
    console.print(f"[yellow]note:[/] --campbell {spec}: a bare number is deprecated; write "
                  f"--campbell \"0:{top:g}:5 rpm\"", highlight=False)
    speeds, unit = parse_speeds(f"0:{top:g}:5 rpm")
    return np.asarray(speeds), unit


@app.command("transmission")
@friendly_errors
def transmission_cmd(
    config: Path = typer.Argument(..., help="TOML config with a \\[transmission] section"),
    revolutions: float | None = typer.Option(
        None, "--revolutions", help="revolutions of the speed-law reference shaft (override)"
    ),
    modes: int = typer.Option(12, "--modes", help="natural frequencies to list"),
    modes_only: bool = typer.Option(False, "--modes-only", help="modal analysis only"),
    out: Path | None = typer.Option(None, "--out", help="output NetCDF file of the time "
                                    "histories (e.g. fe.nc; without it the run is not saved)"),
    netcdf: Path | None = typer.Option(None, "--netcdf", hidden=True,
                                       help="deprecated name of --out"),
    plots: Path | None = typer.Option(None, "--plots", help="directory for IAS figures"),
    shaft: str = typer.Option("output", "--shaft", help="shaft for IAS figures"),
    campbell_spec: str | None = typer.Option(
        None, "--campbell", help="Campbell table at these reference-shaft speeds: "
        "'START:STOP:COUNT UNIT' or 'S1,S2,… UNIT', UNIT rpm (default), rad/s, Hz or rev/s, "
        "e.g. \"0:3000:7 rpm\" (as `geardyn modes --campbell`)"),
    seed: int = typer.Option(0, "--seed", help="seed of the sensors' random draws"),
    force: bool = typer.Option(False, "--force", "--overwrite",
                               help="overwrite an existing --out file"),
    checkpoint_every: float | None = typer.Option(
        None, "--checkpoint-every", help="write the loop state to OUT.ckpt.npz every "
        "SECONDS of wall-clock time (and on Ctrl-C), for --resume"),
    resume: bool = typer.Option(False, "--resume", help="continue a killed or interrupted run "
                                "from OUT.ckpt.npz (same config and options)"),
) -> None:
    """Alias of `geardyn simulate CONFIG --model transmission` (the same run, --out optional),
    printing the static-preload linearised modes first (--modes-only: only them).

    Exit codes: 0 ok; 2 bad input; 3 the run ended diverged, suspect, stopped or reversed
    (with --out the result is written); 130 interrupted by Ctrl-C/SIGTERM (with --out the
    computed part is written with status interrupted). See docs/robustness.md."""
    from geardyn.checkpoint import check_output
    from geardyn.cli.runs import check_run_options
    from geardyn.cli.simulate import run_and_write
    from geardyn.models.transmission import build_model, prepare

    if revolutions is not None and not (math.isfinite(revolutions) and revolutions > 0):
        raise InputError(f"--revolutions: must be a finite number > 0, got {revolutions:g}")
    check_run_options(checkpoint_every)
    out, out_name = renamed_option(out, netcdf, "--out", "--netcdf")
    speeds, speed_unit = parse_campbell(campbell_spec)
    if (checkpoint_every is not None or resume) and out is None:
        raise InputError("--checkpoint-every/--resume need --out (the checkpoint is written "
                         "next to it)")
    if out is not None:
        check_output(out, out_name, overwrite=force or resume)
    cfg = load_config(config)
    if cfg.transmission is None:
        raise ConfigError("no [transmission] section", source=str(config))
    from geardyn.resources import check_run

    check_run(cfg, "transmission", None, revolutions, revolutions_name="--revolutions")
    model = build_model(cfg)
    ref = cfg.transmission.speed_law.reference.shaft if cfg.transmission.speed_law else None
    prep = prepare(model, ref)
    t = Table(title="linearised natural frequencies (Hz, gyroscopic terms neglected)",
              title_justify="left")
    t.add_column("mode", justify="right")
    t.add_column("f (Hz)", justify="right")
    for i, f in enumerate(prep.frequencies_hz[:modes]):
        t.add_row(str(i), f"{f:.2f}")
    console.print(t)
    console.print(f"stable explicit step: {prep.dt_stable:.3e} s")
    if speeds is not None:
        from geardyn.cli.modes import campbell_table, print_campbell

        print_campbell(campbell_table("transmission", cfg, model, speeds, speed_unit, modes,
                                      prepared=prep))
    if modes_only:
        return
    run_and_write(cfg, config, out, model="transmission", seed=seed,
                  revolutions=revolutions, checkpoint_every=checkpoint_every, resume=resume,
                  plots=plots, shaft=shaft, prepared=prep)
