"""Plot of k(θ): total healthy vs faulty overlay and per-pair contributions."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from geardyn.gears.pe_stiffness import StiffnessTable


def plot_stiffness(
    healthy: StiffnessTable,
    path: str | Path,
    faulty: StiffnessTable | None = None,
    title: str | None = None,
) -> Path:
    """Write a PNG: top, total stiffness (healthy and faulty); bottom, each tooth pair's
    contribution (of the faulty table when given)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    x = healthy.mesh_cycle
    ax1.plot(x, healthy.total / 1e8, label="healthy", lw=1.2)
    if faulty is not None:
        ax1.plot(faulty.mesh_cycle, faulty.total / 1e8, label="with faults", lw=1.0)
    ax1.set_ylabel("k [1e8 N/m]")
    ax1.legend(loc="best")
    ax1.grid(True, alpha=0.3)
    src = faulty if faulty is not None else healthy
    # one curve per tooth pair (identified by the mesh count j at which it entered contact)
    j = np.floor(src.mesh_cycle)[:, None] - np.arange(src.pair_stiffness.shape[1])[None, :]
    for jj in np.unique(j):
        sel = (j == jj) & (src.pair_stiffness > 0)
        rows = sel.any(axis=1)
        if rows.sum() < 2:
            continue
        kp = np.where(sel, src.pair_stiffness, 0.0).sum(axis=1)
        idx = np.nonzero(rows)[0]
        ax2.plot(src.mesh_cycle[idx], kp[idx] / 1e8, lw=0.9)
    ax2.set_xlabel("mesh cycles (gear a rotation × z_a / 2π)")
    ax2.set_ylabel("pair k [1e8 N/m]")
    ax2.grid(True, alpha=0.3)
    g = healthy.geometry
    fig.suptitle(title or f"{g.label}: z = {g.a.teeth}/{g.b.teeth}, ε_α = {g.contact_ratio:.3f}")
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
