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
    """Write a PNG: top, total stiffness (healthy and faulty); bottom, pair contributions."""
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
    for p in range(src.pair_stiffness.shape[1]):
        kp = src.pair_stiffness[:, p]
        if np.any(kp > 0):
            ax2.plot(src.mesh_cycle, kp / 1e8, lw=0.8, label=f"pair age {p}")
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
