"""``geardyn simulate CONFIG --out run.nc`` — time simulation of the config's dynamic model
(lumped planetary: Newmark/HHT-α; FE transmission: explicit Verlet) measured by its
``[[sensors]]``, with a progress bar; the result is written as NetCDF in the layout of
docs/results.md."""

from __future__ import annotations

from pathlib import Path

import typer

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors


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
) -> None:
    """Simulate run-up/run-down/stationary operation; writes shaft angles and speeds, mesh
    forces, model states and the sensor channels."""
    import warnings

    from rich.progress import Progress

    from geardyn.config import load_config
    from geardyn.errors import InputError
    from geardyn.results import channels, to_netcdf
    from geardyn.run import run_simulation

    cfg = load_config(config)
    if t_end is not None and t_end <= 0:
        raise InputError(f"--t-end: must be > 0 s, got {t_end:g}")
    if not out.parent.exists():
        raise InputError(f"--out: directory {out.parent} does not exist")
    with Progress(console=console, transient=True) as prog, warnings.catch_warnings(
            record=True) as caught:
        warnings.simplefilter("always")
        task = prog.add_task("simulating", total=1.0)
        ds = run_simulation(cfg, seed=seed, t_end_s=t_end, revolutions=revolutions,
                            progress=lambda f: prog.update(task, completed=f))
    for w in caught:
        console.print(f"[bold yellow]warning:[/] {w.message}", highlight=False)
    ds.attrs["config"] = str(config)
    to_netcdf(ds, out)
    ch = channels(ds)
    console.print(f"wrote {out}: {ds.sizes['time']} samples × {ds.sizes['shaft']} shafts, "
                  f"{len(ch)} sensor channel(s){': ' + ', '.join(ch) if ch else ''}")
    if ds.attrs["status"] != "ok":
        console.print(f"[bold yellow]status {ds.attrs['status']}:[/] {ds.attrs['diagnosis']}",
                      highlight=False)
        raise typer.Exit(code=3)
