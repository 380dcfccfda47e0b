"""Regenerate the figures of docs/validation.md (docs/img/validation_*.png).

    .venv/bin/python docs/validation/make_figures.py            # all (≈ 1 min: 5 FE runs)
    .venv/bin/python docs/validation/make_figures.py --gears    # gear-level figures only

Seed 002 figures use the same runs as tests/validation/seed002 (examples/
seed002_transmission.toml, low-speed shaft IAS, [360 – 430 rpm / 20 rev]); gear-level figures
compare the involute-extended and trochoid roots with ROSS's published mesh stiffness.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
IMG = ROOT / "docs" / "img"
sys.path.insert(0, str(ROOT))  # the seed 002 run helpers live with the validation tests


def _save(fig, name: str) -> None:  # noqa: ANN001
    fig.tight_layout()
    out = IMG / f"validation_{name}.png"
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out.relative_to(ROOT))


def gear_figures() -> None:
    """Tooth profile with and without the trochoid fillet; mesh stiffness against ROSS."""
    from geardyn.gears.geometry import GearBlank, Material, inv, mesh_geometry
    from geardyn.gears.pe_stiffness import mesh_stiffness
    from geardyn.gears.trochoid import trochoid_fillet

    mat = Material(206e9, 0.3, 7810.0)

    def pair(fillet: str):  # noqa: ANN202
        bl = GearBlank(62, rim_radius=0.0175, material=mat, root_fillet=fillet)
        return mesh_geometry(bl, bl, 0.002, math.radians(20.0), 0.020)

    g = pair("trochoid")
    f = trochoid_fillet(g, 0)
    rb, a2 = g.base_radius[0], g.half_angle_base[0]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    gam = np.linspace(math.pi / 2, f.pressure_angle, 200)
    y, h = f.point(gam)
    ax1.plot(h * 1e3, y * 1e3, "C1", label="trochoid fillet (rack tip ρ = 0.38 m)")
    r = np.linspace(g.root_radius[0], g.tip_radius[0], 200)
    th = a2 - inv(np.arccos(np.clip(rb / r, -1, 1)))
    ax1.plot(r * np.sin(th) * 1e3, r * np.cos(th) * 1e3, "C0--", label="involute to the root")
    t = np.linspace(-0.06, 0.06, 200)
    ax1.plot(g.root_radius[0] * np.sin(t) * 1e3, g.root_radius[0] * np.cos(t) * 1e3, "k:",
             lw=0.8, label="root circle")
    ax1.set_xlabel("half thickness h [mm]")
    ax1.set_ylabel("along the tooth centreline y [mm]")
    ax1.set_title("z = 62, m = 2 mm tooth (ROSS test gear)")
    ax1.set_xlim(0, 4)
    ax1.set_ylim(59, 64.5)
    ax1.legend(fontsize=8)
    for fillet, c in (("involute", "C0"), ("trochoid", "C1")):
        tb = mesh_stiffness(pair(fillet), n_per_cycle=256)
        ax2.plot(tb.mesh_cycle, tb.total / 1e6, c, label=f"geardyn, root '{fillet}'")
    ross = [396622921.3581085, 396738680.0375346, 396854147.2919756, 396969323.136738,
            397084207.5865779]
    ax2.axhline(ross[0] / 1e6, color="k", ls=":", lw=1,
                label="ROSS stiffness_range[0] (its own contact start)")
    ax2.set_xlabel("mesh position ξ [mesh cycles]")
    ax2.set_ylabel("mesh stiffness k [MN/m]")
    ax2.set_title("z = 62/62, b = 20 mm")
    ax2.legend(fontsize=8)
    _save(fig, "trochoid_ross")


def seed002_figures() -> None:
    """Figs 14, 17, 18, 19 and 20 of seed 002 from the validation runs."""
    from tests.validation.seed002._runs import (
        BPFO,
        HIGH_MESH,
        PPR,
        detrended,
        mean_difference,
        spectrum,
    )

    from geardyn.signal.cepstrum import real_cepstrum

    o, h = spectrum("healthy")
    sel = o <= 80

    def spec(ax, cases, title):  # noqa: ANN001, ANN202
        for case, c in cases:
            ax.semilogy(o[sel], spectrum(case)[1][sel], c, lw=0.7, label=case)
        ax.set_xlabel("order [events/rev]")
        ax.set_ylabel("IAS amplitude [rad/s]")
        ax.set_title(title)
        ax.legend(fontsize=8)

    fig, ax = plt.subplots(figsize=(10, 3.8))
    spec(ax, [("healthy", "C0"), ("bearing_spall", "C3")],
         "Fig 14: low-speed shaft IAS, healthy vs outer-race spall [360-430 rpm / 20 rev]")
    k = np.arange(1, 18)
    ax.plot(k * BPFO, np.full(k.size, 3e-2), "k.", ms=4, label="k·BPFO")
    ax.axvline(HIGH_MESH, color="g", lw=0.6, ls=":", label="high mesh 69.40 = 15·BPFO")
    ax.legend(fontsize=8)
    _save(fig, "seed002_fig14")

    fig, ax = plt.subplots(figsize=(10, 3.8))
    spec(ax, [("healthy", "C0"), ("crack15", "C1"), ("crack25", "C3")],
         "Fig 17: crack 15 % vs 25 % of the tooth thickness")
    _save(fig, "seed002_fig17")

    fig, ax = plt.subplots(figsize=(10, 3.8))
    spec(ax, [("crack25", "C3"), ("gear_spall", "C2")], "Fig 18: cracked vs spalled wheel")
    _save(fig, "seed002_fig18")

    fig, axs = plt.subplots(1, 2, figsize=(11, 3.8), sharey=True)
    for ax, cases in zip(axs, ([("healthy", "C0"), ("crack15", "C1")],
                               [("gear_spall", "C2"), ("crack25", "C3")]), strict=True):
        for case, c in cases:
            cep = real_cepstrum(detrended(case), float(PPR))
            q = cep.quefrency.values
            m = (q > 0.02) & (q < 4.5)
            ax.plot(q[m], np.abs(cep.values[m]), c, lw=0.7, label=case)
        ax.set_xlabel("quefrency [rev]")
        ax.legend(fontsize=8)
    axs[0].set_ylabel("|real cepstrum| [-]")
    axs[0].set_title("Fig 19 (a)")
    axs[1].set_title("Fig 19 (b)")
    _save(fig, "seed002_fig19")

    fig, (ax, az) = plt.subplots(1, 2, figsize=(11, 3.8))
    ang = np.arange(PPR) / PPR
    for case, c in (("crack25", "C3"), ("gear_spall", "C0")):
        d = np.roll(mean_difference(case), PPR // 4)  # the damaged tooth's passage at ≈ 0.27
        ax.plot(ang, d, c, lw=0.8, label=f"{case} − healthy")
        az.plot(ang, d / np.abs(d).max(), c, lw=0.9, label=f"{case} (normalised)")
    ax.set_xlabel("low-speed shaft angle [rev] (shifted by 0.25)")
    ax.set_ylabel("IAS difference [rad/s]")
    ax.set_title("Fig 20: faulty − healthy IAS, revolutions 3-19 averaged")
    az.set_xlim(0.25, 0.30)
    az.set_xlabel("low-speed shaft angle [rev] (zoom; one mesh cycle = 0.018 rev)")
    az.set_ylabel("normalised difference [-]")
    az.set_title("two impulses: damaged tooth enters, previous pair leaves")
    ax.legend(fontsize=8)
    az.legend(fontsize=8)
    _save(fig, "seed002_fig20")


if __name__ == "__main__":
    gear_figures()
    if "--gears" not in sys.argv:
        seed002_figures()
