"""``geardyn transmission CONFIG``: modes and time simulation of the FE transmission (seed 002)."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import typer
from rich.markup import escape
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
    """Static preload, linearised modes and a speed-law run with IAS outputs.

    Exit codes: 0 ok; 2 bad input or a diverged run; 3 the run ended suspect, stopped or
    reversed; 130 interrupted by Ctrl-C/SIGTERM (with --netcdf the computed part is written
    with status interrupted). See docs/robustness.md."""
    from geardyn.checkpoint import check_output, checkpoint_path
    from geardyn.cli.runs import check_run_options, exit_for_status, finish_run, run_with_control
    from geardyn.models.transmission import build_model, prepare, simulate
    from geardyn.models.transmission.simulate import SimulationDivergedError
    from geardyn.results import to_netcdf
    from geardyn.run import add_sensors

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

        from geardyn.models.transmission.assembly import campbell
        from geardyn.models.transmission.simulate import speed_ratios

        if campbell_rpm <= 0:
            raise ConfigError("--campbell must be > 0 rpm")
        ref_c = ref or next(iter(model.shaft_nodes))
        speeds = np.linspace(0.0, campbell_rpm, 5)
        cd = campbell(model, prep.K_lin, speeds, speed_ratios(model, ref_c), n_modes=modes)
        tc = Table(title=f"Campbell: whirl frequencies (Hz) vs speed of '{ref_c}' (rpm)",
                   title_justify="left")
        tc.add_column("mode", justify="right")
        for sp in speeds:
            tc.add_column(f"{sp:.0f}", justify="right")
        for j in range(cd.sizes["mode"]):
            tc.add_row(str(j), *[f"{x:.2f}" for x in cd.values[:, j]])
        console.print(tc)
    if modes_only:
        return
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            ds = run_with_control(
                cfg, netcdf, checkpoint_every, resume,
                options={"seed": seed, "revolutions": revolutions},
                run=lambda ctl: simulate(cfg, revolutions=revolutions, prepared=prep,
                                         control=ctl, check_step=True))
        for w in caught:
            console.print(f"[bold yellow]warning:[/] {escape(str(w.message))}", highlight=False)
    except SimulationDivergedError as exc:
        if netcdf is not None:
            to_netcdf(exc.result, netcdf)
            console.print(f"partial result written to {netcdf}")
        raise
    add_sensors(cfg, ds, seed)
    a = ds.attrs
    ein, eout = a["energy_input_J"], a["energy_output_J"]
    console.print(
        f"simulated {float(ds.time[-1]):.3f} s in {a['steps']} steps "
        f"({a['wall_integrate_s']:.1f} s); efficiency "
        f"{eout / ein if ein else float('nan'):.3%}"
    )
    ckpt = checkpoint_path(netcdf) if netcdf is not None else None
    if netcdf is not None:
        ds.attrs["config"] = str(config)
    finish_run(ds, netcdf, ckpt)
    if netcdf is not None:
        console.print(f"time histories written to {netcdf} (layout: docs/results.md)")
    if a["status"] == "interrupted":
        exit_for_status(ds, ckpt)
    if plots is not None:
        from geardyn.models.transmission.report import write_figures

        for p in write_figures(ds, cfg, plots, shaft=shaft):
            console.print(f"figure {p}")
    exit_for_status(ds, ckpt)
