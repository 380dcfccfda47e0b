"""``geardyn simulate CONFIG --out run.nc`` — time simulation of the config's dynamic model
(lumped planetary or mechanism model: Newmark/HHT-α; FE transmission: explicit Verlet)
measured by its ``[[sensors]]``, with a progress bar; the result is written as NetCDF in the
layout of docs/results.md. ``geardyn transmission`` is the same run of the FE model
(:func:`run_and_write`)."""

from __future__ import annotations

import math
from pathlib import Path

import typer
from rich.markup import escape

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors
from geardyn.cli.runs import check_run_options, exit_for_status, finish_run, run_with_control
from geardyn.errors import InputError


@app.command("simulate")
@friendly_errors
def simulate_cmd(
    config: Path = typer.Argument(
        ..., help="TOML config with \\[planetary_dynamics.simulation], \\[dynamics.simulation] "
        "or \\[transmission]"),
    out: Path = typer.Option(..., "--out", help="output NetCDF file (e.g. run.nc)"),
    model: str | None = typer.Option(
        None, "--model", help="planetary | mechanism | transmission: the model to run when the "
        "config describes a lumped model and an FE \\[transmission] (as `geardyn modes "
        "--model`)"),
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
    plots: Path | None = typer.Option(
        None, "--plots", help="FE transmission: directory for the IAS figures (order spectrum, "
        "spectrogram, cepstrum of --shaft)"),
    shaft: str = typer.Option("output", "--shaft", help="FE transmission: shaft of the IAS "
                              "figures"),
) -> None:
    """Simulate run-up/run-down/stationary operation; writes shaft angles and speeds, mesh
    forces, model states and the sensor channels.

    The FE transmission (\\[transmission], Thibault et al. 2024) runs here too;
    `geardyn transmission` is
    its alias (with the modal table first).

    Exit codes: 0 ok; 2 bad input; 3 the run ended diverged, suspect, stopped or reversed
    (result written); 130 interrupted by Ctrl-C/SIGTERM (computed part written with status
    interrupted). See docs/robustness.md."""
    from geardyn.checkpoint import check_output
    from geardyn.config import load_config
    from geardyn.errors import InputError

    if t_end is not None and not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"--t-end: must be a finite time > 0 s, got {t_end:g}")
    check_run_options(checkpoint_every)
    check_output(out, "--out", overwrite=force or resume)
    cfg = load_config(config)
    run_and_write(cfg, config, out, model=model, seed=seed, t_end=t_end,
                  revolutions=revolutions, checkpoint_every=checkpoint_every, resume=resume,
                  plots=plots, shaft=shaft)


def run_and_write(cfg, config: Path, out: Path | None, *, model: str | None = None,  # noqa: ANN001
                  seed: int = 0, t_end: float | None = None, revolutions: float | None = None,
                  checkpoint_every: float | None = None, resume: bool = False,
                  plots: Path | None = None, shaft: str = "output",
                  prepared=None) -> None:  # noqa: ANN001
    """The run of ``geardyn simulate`` (and of its alias ``geardyn transmission``): the model
    :func:`geardyn.run.simulated_model` picks, under progress bar, Ctrl-C and checkpoint
    control, written atomically to ``out`` (if given), IAS figures of an FE run in ``plots``,
    exit code from the run's status. ``prepared``: the FE preparation already computed (the
    alias prints its modes first), reused instead of recomputed."""
    import warnings

    from geardyn.checkpoint import checkpoint_path
    from geardyn.results import channels
    from geardyn.run import simulated_model

    kind = simulated_model(cfg, model)
    if revolutions is not None and kind != "transmission":
        raise InputError(f"--revolutions: sets the run length of the FE transmission model "
                         f"([transmission] speed law); this run is the {kind} model: use "
                         "--t-end")
    from geardyn.resources import check_run

    check_run(cfg, kind, t_end, revolutions, t_end_name="--t-end",
              revolutions_name="--revolutions")
    if plots is not None:
        if kind != "transmission":
            raise InputError("--plots: IAS figures are written for the FE transmission only "
                             f"(this run is the {kind} model)")
        if plots.exists() and not plots.is_dir():
            raise InputError(f"--plots: '{plots}' is a file, expected a directory (created if "
                             "missing)")
        if shaft not in [s.name for s in cfg.transmission.shafts]:
            raise InputError(f"--shaft: unknown shaft '{shaft}' (one of "
                             f"{', '.join(s.name for s in cfg.transmission.shafts)})")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = run_with_control(
            cfg, out, checkpoint_every, resume,
            options={"seed": seed, "t_end_s": t_end, "revolutions": revolutions},
            run=lambda ctl: _run(cfg, seed, t_end, revolutions, ctl, kind, prepared))
    for w in caught:
        console.print(f"[bold yellow]warning:[/] {escape(str(w.message))}", highlight=False)
    ckpt = checkpoint_path(out) if out is not None else None
    if out is not None:
        ds.attrs["config"] = str(config)
    finish_run(ds, out, ckpt)
    a = ds.attrs
    if kind == "transmission" and "energy_input_J" in a:
        ein, eout = a["energy_input_J"], a["energy_output_J"]
        eff = f"efficiency {eout / ein:.3%}" if ein else "no drive power (efficiency n/a)"
        console.print(
            f"simulated {float(ds.time[-1]):.3f} s in {a['steps']} steps "
            f"({a['wall_integrate_s']:.1f} s, {a.get('integrator', 'explicit')}); {eff}")
    ch = channels(ds)
    where = f"wrote {out}" if out is not None else "simulated (no output file)"
    console.print(f"{where}: {ds.sizes['time']} samples × {ds.sizes['shaft']} shafts, "
                  f"{len(ch)} sensor channel(s){': ' + ', '.join(ch) if ch else ''}")
    if plots is not None and a.get("status") != "interrupted":
        from geardyn.models.transmission.report import write_figures

        for p in write_figures(ds, cfg, plots, shaft=shaft):
            console.print(f"figure {p}")
    exit_for_status(ds, ckpt)


def _run(cfg, seed: int, t_end: float | None, revolutions: float | None,  # noqa: ANN001
         control, kind: str | None = None, prepared=None):  # noqa: ANN001, ANN202
    from geardyn.run import run_simulation

    return run_simulation(cfg, seed=seed, t_end_s=t_end, revolutions=revolutions,
                          control=control, model=kind, prepared=prepared)
