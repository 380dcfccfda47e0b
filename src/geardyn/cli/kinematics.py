"""``geardyn kinematics CONFIG --input LINK=RPM ...``: ratios and characteristic frequencies."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import typer
from rich.console import Console
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors, parse_assignments
from geardyn.config import load_config
from geardyn.kinematics import (
    CharacteristicFrequencies,
    KinematicAnalysis,
    analyze_kinematics,
    characteristic_frequencies,
)


def df_table(df: pd.DataFrame, title: str, floatfmt: str = "{:.6g}") -> Table:
    """A rich table from a DataFrame (floats with 6 significant digits)."""
    table = Table(title=title, title_justify="left", show_lines=False)
    for c in df.columns:
        table.add_column(str(c), justify="right" if df[c].dtype.kind in "fiu" else "left")
    for _, row in df.iterrows():
        cells = []
        for v in row:
            if isinstance(v, float | np.floating):
                cells.append("" if math.isnan(v) else floatfmt.format(v))
            else:
                cells.append(str(v))
        table.add_row(*cells)
    return table


def render_kinematics(
    analysis: KinematicAnalysis, freqs: CharacteristicFrequencies, out: Console | None = None
) -> None:
    """Print the analysis (DOF, carriers) and all frequency tables."""
    out = out or console
    g = analysis.graph
    out.print(
        f"[bold]{g.name}[/]: {len(g.links)} links, {len(g.meshes)} gear pairs, "
        f"rank(M) = {analysis.rank}, DOF = {analysis.dof}; inputs "
        + ", ".join(f"{k} = {v:g} rpm" for k, v in freqs.inputs_rpm.items())
        + f"; orders per rev of '{freqs.order_reference}' ({freqs.reference_hz:.6g} Hz)"
    )
    out.print(df_table(freqs.links, "Links (ratio: velocity ratio to each input, polar form)"))
    out.print(df_table(freqs.meshes, "Gear pairs (carrier = reference link, seed 000 eq 1)"))
    out.print(df_table(freqs.wheels, "Wheels: tooth-fault frequency (one tooth, all meshes)"))
    if not freqs.planet_pass.empty:
        out.print(df_table(freqs.planet_pass, "Planet pass"))
    if not freqs.bearings.empty:
        out.print(df_table(freqs.bearings, "Bearings (FTF relative to the outer ring)"))
    for note in freqs.notes:
        out.print(f"[yellow]note:[/] {note}")


@app.command("kinematics")
@friendly_errors
def kinematics_cmd(
    config: Path = typer.Argument(..., help="TOML file describing the mechanism"),
    input: list[str] = typer.Option(  # noqa: A002
        None, "--input", "-i", help="input speed LINK=RPM (signed); repeat for several inputs"
    ),
    order_ref: str = typer.Option(None, "--order-ref", help="link defining order 1"),
    as_json: bool = typer.Option(False, "--json", help="print JSON instead of tables"),
    matrices: bool = typer.Option(
        False, "--matrices", help="also print the adjacency table T and constraint matrix M"
    ),
) -> None:
    """Degrees of freedom, carriers, velocity ratios and characteristic frequencies."""
    cfg = load_config(config)
    analysis = analyze_kinematics(cfg)
    speeds = parse_assignments(input, "--input") or dict(cfg.input_speeds_rpm)
    freqs = characteristic_frequencies(analysis, speeds, order_reference=order_ref)
    if as_json:
        typer.echo(freqs.to_json())
    else:
        if matrices:
            console.print(df_table(analysis.adjacency_frame().reset_index(), "Adjacency table T"))
            m = analysis.constraint_frame().map(lambda z: f"{complex(z):.4g}".strip("()"))
            console.print(df_table(m.reset_index(), "Constraint matrix M (row 0: frame)"))
        render_kinematics(analysis, freqs)
