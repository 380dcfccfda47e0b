"""``geardyn modes CONFIG`` — natural frequencies, mode types and energies of the config's
lumped model: the planetary model (``[planetary_dynamics]``, seed 003 ch. 3) or the general
torsional model of any mechanism (``[dynamics]``, docs/dynamics.md), with optional mode-shape /
energy plots."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors


@app.command("modes")
@friendly_errors
def modes_cmd(
    config: Path = typer.Argument(..., help="TOML config with a [planetary_dynamics] or "
                                  "[dynamics] section"),
    reduction: str | None = typer.Option(
        None, "--reduction", help="override: none | torsional | transverse (planetary model)"),
    model_kind: str | None = typer.Option(
        None, "--model", help="planetary | mechanism (default: planetary when the config has "
        "[planetary_dynamics], else the [dynamics] model of the mechanism)"),
    max_hz: float | None = typer.Option(None, "--max-hz", help="list modes up to this (Hz)"),
    plot: Path | None = typer.Option(None, "--plot", help="PNG: kinetic/strain energy per "
                                     "mode (up to --max-hz)"),
    netcdf: Path | None = typer.Option(None, "--netcdf", help="write frequencies, shapes, "
                                       "energy fractions (xarray)"),
) -> None:
    """Natural frequencies, multiplicities, mode types, dominant motion and strain energy."""
    from geardyn.config import load_config
    from geardyn.errors import ConfigError, InputError

    cfg = load_config(config)
    kind = model_kind or ("planetary" if cfg.planetary_dynamics is not None else "mechanism")
    if kind not in ("planetary", "mechanism"):
        raise InputError(f"--model: must be 'planetary' or 'mechanism', got {kind!r}")
    if kind == "mechanism":
        from geardyn.models.core import model_from_config as core_model
        from geardyn.models.core.modal import core_modes

        if cfg.dynamics is None:
            raise ConfigError("the config has neither [planetary_dynamics] nor [dynamics] "
                              "(see docs/dynamics.md)")
        model = core_model(cfg)
        res = core_modes(model)
        title = f"modes of {config.name} ({model.n} DOF, torsional model of the mechanism)"
        plot_model = None
    else:
        from geardyn.models.planetary.build import model_from_config
        from geardyn.solve.modal import modes

        model = model_from_config(cfg, reduction)
        res = modes(model)
        title = (f"modes of {config.name} ({len(model.names)} DOF, reduction "
                 f"{model.reduction})")
        plot_model = model
    t = Table(title=title, title_justify="left")
    for c in ("mode", "f (Hz)", "mult.", "type", "dominant motion", "dominant strain energy"):
        t.add_column(c, justify="right" if c in ("mode", "f (Hz)", "mult.") else "left")
    for row in res.table():
        if max_hz is not None and row["freq_hz"] > max_hz:
            break
        t.add_row(str(row["mode"]), f"{row['freq_hz']:.1f}", str(row["multiplicity"]),
                  row["type"], row["dominant_motion"], row["dominant_strain"])
    console.print(t)
    if netcdf is not None:
        from geardyn.checkpoint import write_atomic

        write_atomic(netcdf, lambda tmp: res.to_dataset().to_netcdf(tmp, engine="h5netcdf"))
        console.print(f"wrote {netcdf}")
    if plot is not None:
        from geardyn.plotting import save_figure

        save_figure(res.plot(model=plot_model, max_hz=max_hz), plot)
        console.print(f"wrote {plot}")
