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
    plot: Path | None = typer.Option(None, "--plot", help="PNG: kinetic/strain energy per mode"),
    netcdf: Path | None = typer.Option(None, "--netcdf", help="write frequencies, shapes, "
                                       "energy fractions (xarray)"),
) -> None:
    """Natural frequencies, multiplicities, mode types, dominant motion and strain energy."""
    from geardyn.config import load_config
    from geardyn.models.planetary.build import model_from_config
    from geardyn.solve.modal import modes, strain_energy_table

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
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        labels, strain = strain_energy_table(model, res)
        ek = res.kinetic / res.kinetic.sum(1, keepdims=True).clip(1e-300)
        n = len(res.freq_hz)
        fig, ax = plt.subplots(1, 2, figsize=(14, 0.25 * n + 2))
        ax[0].imshow(ek * 100, aspect="auto", cmap="viridis")
        ax[0].set_xticks(range(len(res.dof_names)), res.dof_names, rotation=90, fontsize=6)
        ax[0].set_title("modal kinetic energy per DOF (%) — seed 003 Table 3.4 layout")
        im = ax[1].imshow(strain * 100, aspect="auto", cmap="viridis")
        ax[1].set_xticks(range(len(labels)), labels, rotation=90, fontsize=5)
        ax[1].set_title("modal strain energy per spring (%) — Table 3.5 layout")
        for a in ax:
            a.set_yticks(range(n), [f"{f:.0f} Hz" for f in res.freq_hz], fontsize=6)
        fig.colorbar(im, ax=ax[1])
        fig.tight_layout()
        fig.savefig(plot, dpi=110)
        plt.close(fig)
        console.print(f"wrote {plot}")
