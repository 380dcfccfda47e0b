"""``geardyn transmission CONFIG``: alias of ``geardyn simulate`` for the FE transmission (seed
002), with its linearised modes (and optionally a Campbell table) printed first. The run is the
same code as ``simulate`` (:func:`geardyn.cli.simulate.run_and_write`)."""

from __future__ import annotations

import math
from pathlib import Path

import typer
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors
from geardyn.config import load_config
from geardyn.errors import ConfigError, InputError


@app.command("transmission")
@friendly_errors
def transmission_cmd(
    config: Path = typer.Argument(..., help="TOML config with a \\[transmission] section"),
    revolutions: float | None = typer.Option(
        None, "--revolutions", help="revolutions of the speed-law reference shaft (override)"
    ),
    modes: int = typer.Option(12, "--modes", help="natural frequencies to list"),
    modes_only: bool = typer.Option(False, "--modes-only", help="modal analysis only"),
    netcdf: Path | None = typer.Option(None, "--netcdf", help="write the time histories"),
    plots: Path | None = typer.Option(None, "--plots", help="directory for IAS figures"),
    shaft: str = typer.Option("output", "--shaft", help="shaft for IAS figures"),
    campbell_rpm: float | None = typer.Option(
        None, "--campbell", help="Campbell table up to this reference-shaft speed (rpm)"
    ),
    seed: int = typer.Option(0, "--seed", help="seed of the sensors' random draws"),
    force: bool = typer.Option(False, "--force", "--overwrite",
                               help="overwrite an existing --netcdf file"),
    checkpoint_every: float | None = typer.Option(
        None, "--checkpoint-every", help="write the loop state to NETCDF.ckpt.npz every "
        "SECONDS of wall-clock time (and on Ctrl-C), for --resume"),
    resume: bool = typer.Option(False, "--resume", help="continue a killed or interrupted run "
                                "from NETCDF.ckpt.npz (same config and options)"),
) -> None:
    """Alias of `geardyn simulate CONFIG --model transmission` (the same run, options named
    --netcdf instead of --out and an optional output file), printing the static-preload
    linearised modes first (--modes-only: only them).

    Exit codes: 0 ok; 2 bad input; 3 the run ended diverged, suspect, stopped or reversed
    (with --netcdf the result is written); 130 interrupted by Ctrl-C/SIGTERM (with --netcdf the
    computed part is written with status interrupted). See docs/robustness.md."""
    from geardyn.checkpoint import check_output
    from geardyn.cli.runs import check_run_options
    from geardyn.cli.simulate import run_and_write
    from geardyn.models.transmission import build_model, prepare

    if revolutions is not None and not (math.isfinite(revolutions) and revolutions > 0):
        raise InputError(f"--revolutions: must be a finite number > 0, got {revolutions:g}")
    check_run_options(checkpoint_every)
    if (checkpoint_every is not None or resume) and netcdf is None:
        raise InputError("--checkpoint-every/--resume need --netcdf (the checkpoint is written "
                         "next to it)")
    if netcdf is not None:
        check_output(netcdf, "--netcdf", overwrite=force or resume)
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
    if campbell_rpm is not None:
        import numpy as np

        from geardyn.cli.modes import campbell_table, print_campbell

        if campbell_rpm <= 0:
            raise ConfigError("--campbell must be > 0 rpm")
        speeds = np.linspace(0.0, campbell_rpm, 5)
        print_campbell(campbell_table("transmission", cfg, model, speeds, "rpm", modes,
                                      prepared=prep))
    if modes_only:
        return
    run_and_write(cfg, config, netcdf, model="transmission", seed=seed,
                  revolutions=revolutions, checkpoint_every=checkpoint_every, resume=resume,
                  plots=plots, shaft=shaft, prepared=prep)
