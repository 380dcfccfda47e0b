"""Figures of mesh stiffness k(ξ): one table (:func:`plot_stiffness_table`, also
``StiffnessTable.plot()``), the healthy/faulty overlay with each tooth pair's contribution
(:func:`stiffness_figure`) and a thin save helper for the CLI (:func:`plot_stiffness`).

The functions return figures and never save or switch the backend (see
:mod:`geardyn.plotting`); the x axis is the mesh position ξ = z_a·φ_a/(2π) [mesh cycles], the
y axis the stiffness along the transverse line of action [N/m].
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from geardyn.plotting import new_axes, save_figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from geardyn.gears.pe_stiffness import StiffnessTable

MESH_POSITION = "mesh position ξ = z_a·φ_a/2π [mesh cycles]"
STIFFNESS = "mesh stiffness k [N/m]"
PAIR_STIFFNESS = "tooth-pair stiffness [N/m]"


def pair_curves(table: StiffnessTable) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """``(ξ, k)`` of each tooth pair while in contact (a pair is identified by the mesh count
    at which it entered contact)."""
    j = np.floor(table.mesh_cycle)[:, None] - np.arange(table.pair_stiffness.shape[1])[None, :]
    for jj in np.unique(j):
        sel = (j == jj) & (table.pair_stiffness > 0)
        rows = np.nonzero(sel.any(axis=1))[0]
        if rows.size < 2:
            continue
        kp = np.where(sel, table.pair_stiffness, 0.0).sum(axis=1)
        yield table.mesh_cycle[rows], kp[rows]


def plot_stiffness_table(table: StiffnessTable, ax: Axes | None = None, label: str | None = None,
                         pairs: bool = False, xmax: float | None = None, **line_kw: Any
                         ) -> Figure:
    """Total mesh stiffness against mesh position; ``pairs`` adds each tooth pair's
    contribution (thin lines); ``xmax`` [mesh cycles] limits the x axis; ``line_kw`` go to
    ``ax.plot`` for the total."""
    fig, ax = new_axes(ax, (9, 4))
    g = table.geometry
    ax.plot(table.mesh_cycle, table.total, label=label or "total", **{"lw": 1.2, **line_kw})
    if pairs:
        for i, (x, k) in enumerate(pair_curves(table)):
            ax.plot(x, k, lw=0.7, color="0.5", label="tooth pairs" if i == 0 else None)
    ax.set_xlim(float(table.mesh_cycle[0]), xmax if xmax is not None else
                float(table.mesh_cycle[-1]))
    ax.set_xlabel(MESH_POSITION)
    ax.set_ylabel(STIFFNESS)
    ax.grid(True, alpha=0.3)
    if pairs or label:
        ax.legend(loc="best", fontsize=8)
    if not ax.get_title():
        ax.set_title(f"{g.label}: z = {g.a.teeth}/{g.b.teeth}, ε_α = {g.contact_ratio:.3f}")
    return fig


def stiffness_figure(healthy: StiffnessTable, faulty: StiffnessTable | None = None,
                     title: str | None = None, xmax: float | None = None) -> Figure:
    """Top: total stiffness, healthy and with faults; bottom: each tooth pair's contribution
    (of the faulty table when given). ``xmax`` [mesh cycles] limits both x axes."""
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True, layout="constrained")
    plot_stiffness_table(healthy, ax1, label="healthy", xmax=xmax)
    if faulty is not None:
        ax1.plot(faulty.mesh_cycle, faulty.total, label="with faults", lw=1.0)
        ax1.legend(loc="best", fontsize=8)
    for i, (x, k) in enumerate(pair_curves(faulty if faulty is not None else healthy)):
        ax2.plot(x, k, lw=0.9, label=f"tooth pair {i + 1}")
    if ax2.get_lines():
        ax2.legend(loc="upper right", fontsize=7, ncol=min(4, len(ax2.get_lines())),
                   title="one curve per tooth pair in contact", title_fontsize=7)
    ax2.set_xlabel(MESH_POSITION)
    ax2.set_ylabel(PAIR_STIFFNESS)
    ax2.grid(True, alpha=0.3)
    g = healthy.geometry
    ax1.set_title("")
    fig.suptitle(title or f"{g.label}: z = {g.a.teeth}/{g.b.teeth}, ε_α = {g.contact_ratio:.3f}")
    return fig


def plot_stiffness(
    healthy: StiffnessTable,
    path: str | Path,
    faulty: StiffnessTable | None = None,
    title: str | None = None,
) -> Path:
    """Write :func:`stiffness_figure` to ``path`` (PNG, …) and close it (for the CLI)."""
    return save_figure(stiffness_figure(healthy, faulty, title), path)
