"""``geardyn stiffness CONFIG --pair NAME [--plot out.png]``: geometry and mesh stiffness k(θ)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import (
    check_number,
    check_output_file,
    console,
    friendly_errors,
    renamed_option,
)
from geardyn.config import load_config
from geardyn.errors import ConfigError
from geardyn.models.gear_pairs import pair_model, pair_names


def summary_row(key: str, value: float) -> tuple[str, str]:
    """A geometry summary entry as (label with its unit, value in that unit): lengths
    (``…_m``) in mm, angles (``…_deg``) in degrees, ratios without unit."""
    if key.endswith("_m"):
        return f"{key[:-2]} (mm)", f"{value * 1e3:.4f}"
    if key.endswith("_deg"):
        return f"{key[:-4]} (deg)", f"{value:.4f}"
    return f"{key} (-)", f"{value:.5f}"


@app.command("stiffness")
@friendly_errors
def stiffness_cmd(
    config: Path = typer.Argument(..., help="TOML config with [[gear_geometry]] entries"),
    pair: str | None = typer.Option(None, "--pair", help="gear pair name (default: all pairs)"),
    plot: Path | None = typer.Option(None, "--plot", help="write k(θ) to this PNG"),
    cycles: float = typer.Option(2.0, "--cycles", help="mesh cycles to tabulate/plot"),
    hunting: bool = typer.Option(False, "--hunting", help="tabulate a full hunting period"),
    samples: int = typer.Option(128, "--samples", help="samples per mesh cycle"),
    out: Path | None = typer.Option(None, "--out", help="NetCDF file of the k(θ) table "
                                    "(one pair: --pair NAME when the config has several)"),
    netcdf: Path | None = typer.Option(None, "--netcdf", hidden=True,
                                       help="deprecated name of --out"),
    force: bool = typer.Option(False, "--force", help="overwrite an existing --out file"),
) -> None:
    """Gear-pair geometry and potential-energy mesh stiffness (healthy and with faults)."""
    from geardyn.gears.loaded import static_transmission_error
    from geardyn.gears.pe_stiffness import mesh_stiffness
    from geardyn.gears.plot import plot_stiffness

    check_number(cycles, "--cycles", gt=0, le=1e4)
    check_number(samples, "--samples", ge=4, le=1 << 16)
    if plot is not None:
        check_output_file(plot, "--plot")
    netcdf, out_name = renamed_option(out, netcdf, "--out", "--netcdf")
    if netcdf is not None:
        from geardyn.checkpoint import check_output

        check_output_file(netcdf, out_name)
        check_output(netcdf, out_name, overwrite=force)
    cfg = load_config(config)
    names = [pair] if pair else pair_names(cfg)
    if not names:
        raise ConfigError("the config has no [[gear_geometry]] entries", source=str(config))
    if plot is not None and len(names) > 1:
        raise ConfigError("--plot needs --pair NAME when the config has several pairs")
    if netcdf is not None and len(names) > 1:  # one file, one pair's table
        raise ConfigError(f"{out_name} needs --pair NAME when the config has several pairs")
    for name in names:
        pm = pair_model(cfg, name)
        g = pm.geometry
        n_cycles = None if hunting else cycles
        healthy = mesh_stiffness(g, n_per_cycle=samples, n_cycles=n_cycles)
        faulty = (
            mesh_stiffness(g, n_per_cycle=samples, n_cycles=n_cycles, faults=pm.faults)
            if pm.faults
            else None
        )
        t = Table(
            title=f"gear pair '{name}' (z = {g.a.teeth}/{g.b.teeth}"
            f"{', internal' if g.internal else ''})",
            title_justify="left",
        )
        t.add_column("quantity")
        t.add_column("value", justify="right")
        for k, v in g.summary().items():
            t.add_row(*summary_row(k, v))
        k = healthy.total
        t.add_row("k mean (N/m)", f"{k.mean():.4e}")
        t.add_row("k min / max (N/m)", f"{k.min():.4e} / {k.max():.4e}")
        t.add_row("fluctuation (max−min)/mean", f"{np.ptp(k) / k.mean():.4f}")
        t.add_row("torsional mean k·r_b,a² (N·m/rad)", f"{healthy.torsional.mean():.4e}")
        if faulty is not None:
            kf = faulty.total
            t.add_row("with faults: k min (N/m)", f"{kf.min():.4e}")
            t.add_row("max stiffness loss", f"{np.max(1 - kf / k):.2%}")
        if pm.torque is not None:
            ste = static_transmission_error(
                g, pm.torque, n_per_cycle=min(samples, 64), corrections=pm.corrections
            )
            t.add_row(f"loaded ({pm.torque:g} N·m): STE mean (µm)", f"{ste.ste.mean() * 1e6:.3f}")
            t.add_row("loaded: STE peak-to-peak (µm)", f"{np.ptp(ste.ste) * 1e6:.3f}")
            t.add_row("loaded: mean W/STE (N/m)", f"{ste.secant_stiffness.mean():.4e}")
        console.print(t)
        if netcdf is not None:
            from geardyn.checkpoint import write_atomic

            table = (faulty or healthy).to_xarray()
            write_atomic(netcdf, lambda tmp, table=table: table.to_netcdf(tmp, engine="h5netcdf"))
            console.print(f"table written to {netcdf}")
        if plot is not None:
            plot_stiffness(healthy, plot, faulty)
            console.print(f"plot written to {plot}")
