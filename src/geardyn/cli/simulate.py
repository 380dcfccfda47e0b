"""``geardyn simulate CONFIG --out run.nc`` — time simulation of the lumped planetary model
(Newmark/HHT-α, numba), with a progress bar; results as NetCDF (xarray)."""

from __future__ import annotations

from pathlib import Path

import typer

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors


@app.command("simulate")
@friendly_errors
def simulate_cmd(
    config: Path = typer.Argument(..., help="TOML config with [planetary_dynamics.simulation]"),
    out: Path = typer.Option(..., "--out", help="output NetCDF file (e.g. run.nc)"),
    t_end: float | None = typer.Option(None, "--t-end", help="override t_end_s (s)"),
) -> None:
    """Simulate run-up/run-down/stationary operation; writes DOF histories, mesh forces, DTE,
    load-sharing ratios and bearing forces."""
    from rich.progress import Progress

    from geardyn.config import load_config
    from geardyn.errors import ConfigError
    from geardyn.models.planetary.build import prepare
    from geardyn.models.planetary.dynamics import simulate

    cfg = load_config(config)
    p = prepare(cfg)
    sim = cfg.planetary_dynamics.simulation  # type: ignore[union-attr]
    t1 = t_end if t_end is not None else sim.t_end_s
    if t1 <= 0:
        raise ConfigError("--t-end must be > 0")
    with Progress(console=console, transient=True) as prog:
        task = prog.add_task(f"simulating {t1:g} s", total=1.0)
        ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, t1, sim.dt_s,
                      save_every=sim.save_every, alpha=sim.hht_alpha,
                      progress=lambda f: prog.update(task, completed=f))
    ds.attrs["config"] = str(config)
    ds.to_netcdf(out, engine="h5netcdf")
    console.print(f"wrote {out}: {ds.sizes['time']} samples × {ds.sizes['dof']} DOF, "
                  f"{ds.attrs['wall_time_s']:.2f} s wall")
    if ds.attrs["status"] != "ok":
        console.print(f"[bold yellow]warning:[/] {ds.attrs['diagnosis']}")
        raise typer.Exit(code=3)
