"""``geardyn kinematics CONFIG --input LINK=RPM ...``: ratios and characteristic frequencies."""

from __future__ import annotations

import json
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

#: Widest table printed (characters); wider tables are split into column groups.
TABLE_WIDTH = 100


def _cell(v: object, floatfmt: str) -> str:
    if isinstance(v, float | np.floating):
        return "" if math.isnan(v) else floatfmt.format(v)
    return str(v)


def df_tables(df: pd.DataFrame, title: str, floatfmt: str = "{:.6g}",
              width: int = TABLE_WIDTH) -> list[Table]:
    """Rich tables from a DataFrame (floats with 6 significant digits), each at most ``width``
    characters wide: a wide frame is split into column groups, each repeating the first (key)
    column, titled ``(columns i-j of n)``."""
    cells = {c: [_cell(v, floatfmt) for v in df[c]] for c in df.columns}
    need = {c: max([len(str(c)), *(len(x) for x in cells[c])]) + 3 for c in df.columns}
    cols = list(df.columns)
    if not cols:
        return [Table(title=title, title_justify="left")]
    key, rest = cols[0], cols[1:]
    groups: list[list] = []
    current: list = []
    used = need[key] + 1
    for c in rest:
        if current and used + need[c] > width:
            groups.append(current)
            current, used = [], need[key] + 1
        current.append(c)
        used += need[c]
    groups.append(current)
    tables = []
    for i, group in enumerate(groups):
        part = "" if len(groups) == 1 else f" (part {i + 1} of {len(groups)})"
        table = Table(title=title + part, title_justify="left", show_lines=False)
        for c in [key, *group]:
            table.add_column(str(c), justify="right" if df[c].dtype.kind in "fiu" else "left",
                             no_wrap=True)
        for r in range(len(df)):
            table.add_row(*(cells[c][r] for c in [key, *group]))
        tables.append(table)
    return tables


def df_table(df: pd.DataFrame, title: str, floatfmt: str = "{:.6g}") -> Table:
    """One rich table from a DataFrame (wide frames: see :func:`df_tables`)."""
    return df_tables(df, title, floatfmt, width=10**6)[0]


def print_df(out: Console, df: pd.DataFrame, title: str) -> None:
    """Print a DataFrame as tables fitting :data:`TABLE_WIDTH` columns."""
    for table in df_tables(df, title):
        out.print(table)


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
    print_df(out, freqs.links, "Links (ratio: velocity ratio to each input, polar form)")
    print_df(out, freqs.meshes, "Gear pairs (carrier = reference link, Penaud et al. 2012, eq 1)")
    print_df(out, freqs.wheels, "Wheels: tooth-fault frequency (one tooth, all meshes)")
    if not freqs.planet_pass.empty:
        print_df(out, freqs.planet_pass, "Planet pass")
    if not freqs.bearings.empty:
        print_df(out, freqs.bearings, "Bearings (FTF relative to the outer ring)")
    for note in freqs.notes:
        out.print(f"[yellow]note:[/] {note}")


def kinematics_json(analysis: KinematicAnalysis, freqs: CharacteristicFrequencies) -> dict:
    """The frequencies as plain JSON numbers: each link's velocity ratio to each input as
    ``{"real", "imag", "magnitude", "angle_deg"}`` (Penaud et al. 2012, eq 5; real for planar
    mechanisms, complex for bevel/spatial ones) instead of the table's display string."""
    out = freqs.to_dict()
    inputs = list(freqs.inputs_rpm)
    ratios = analysis.velocity_ratios(inputs)
    index = {name: i for i, name in enumerate(analysis.graph.links)}
    for row in out["links"]:
        r = ratios[index[row["link"]]]
        row["ratio"] = {
            name: {"real": float(z.real), "imag": float(z.imag), "magnitude": float(abs(z)),
                   "angle_deg": math.degrees(math.atan2(z.imag, z.real)) if abs(z) > 0 else 0.0}
            for name, z in zip(inputs, (complex(v) for v in r), strict=True)
        }
    return out


@app.command("kinematics")
@friendly_errors
def kinematics_cmd(
    config: Path = typer.Argument(..., help="TOML file describing the mechanism"),
    input: list[str] = typer.Option(  # noqa: A002
        None, "--input", "-i", help="input speed LINK=RPM, signed about the link's own axis "
        "(docs/kinematics.md); repeat for several inputs"
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
        typer.echo(json.dumps(kinematics_json(analysis, freqs), indent=2, ensure_ascii=False))
    else:
        if matrices:
            print_df(console, analysis.adjacency_frame().reset_index(), "Adjacency table T")
            m = analysis.constraint_frame().map(lambda z: f"{complex(z):.4g}".strip("()"))
            print_df(console, m.reset_index(), "Constraint matrix M (row 0: frame)")
        render_kinematics(analysis, freqs)
