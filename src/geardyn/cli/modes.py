"""``geardyn modes CONFIG`` — natural frequencies, mode types and energies of the lumped
planetary model (seed 003 ch. 3), with optional mode-shape / energy plots."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors


@app.command("modes")
@friendly_errors
def modes_cmd(
    config: Path = typer.Argument(..., help="TOML config with a [planetary_dynamics] section"),
    reduction: str | None = typer.Option(
        None, "--reduction", help="override: none | torsional | transverse"),
    max_hz: float | None = typer.Option(None, "--max-hz", help="list modes up to this (Hz)"),
    plot: Path | None = typer.Option(None, "--plot", help="PNG: kinetic/strain energy per "
                                     "mode (up to --max-hz)"),
    netcdf: Path | None = typer.Option(None, "--netcdf", help="write frequencies, shapes, "
                                       "energy fractions (xarray)"),
) -> None:
    """Natural frequencies, multiplicities, mode types, dominant motion and strain energy."""
    from geardyn.config import load_config
    from geardyn.models.planetary.build import model_from_config
    from geardyn.solve.modal import modes

    cfg = load_config(config)
    model = model_from_config(cfg, reduction)
    res = modes(model)
    t = Table(title=f"modes of {config.name} ({len(model.names)} DOF, reduction "
              f"{model.reduction})", title_justify="left")
    for c in ("mode", "f (Hz)", "mult.", "type", "dominant motion", "dominant strain energy"):
        t.add_column(c, justify="right" if c in ("mode", "f (Hz)", "mult.") else "left")
    for row in res.table():
        if max_hz is not None and row["freq_hz"] > max_hz:
            break
        t.add_row(str(row["mode"]), f"{row['freq_hz']:.1f}", str(row["multiplicity"]),
                  row["type"], row["dominant_motion"], row["dominant_strain"])
    console.print(t)
    if netcdf is not None:
        res.to_dataset().to_netcdf(netcdf, engine="h5netcdf")
        console.print(f"wrote {netcdf}")
    if plot is not None:
        from geardyn.plotting import save_figure

        save_figure(res.plot(model=model, max_hz=max_hz), plot)
        console.print(f"wrote {plot}")
