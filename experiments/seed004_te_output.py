"""Experiment: seed 004 §8.3 case 3 vs case 2 ("tooth mesh cycle becomes unclear and the
irregularity is increased"): share of the sun / carrier torsional speed variance at integer mesh
orders, and its peak to peak, with and without the combined transmission error."""
from __future__ import annotations

import sys

import numpy as np

sys.path.append("tests")
from validation.seed004._reclaimer import R_C, ZR, run  # noqa: E402


def wheel(d):
    st = d["planetary_dynamics"]["stages"][0]
    st["carrier"]["inertia_kgm2"], st["carrier"]["mass_kg"] = 92926.0, 26431.0


def mesh_share(ds, dof, t0=2.0, spc=64):
    t = ds.time.values
    x = ZR * ds.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
    s = t > t0
    n = int(np.floor(x[s][-1] - x[s][0]))
    g = x[s][0] + np.arange(n * spc) / spc
    y = np.interp(g, x[s], ds.v.sel(dof=dof).values[s])
    y = y - np.polyval(np.polyfit(g, y, 1), g)
    p = np.abs(np.fft.rfft(y)) ** 2
    p[0] = 0
    return p[n::n].sum() / p.sum(), np.ptp(y)


if __name__ == "__main__":
    for te in (False, True):
        _, ds = run([], 8.0, te=te, edit=wheel)
        for dof in ("sun.u", "carrier.u", "ring.u", "planet1.u"):
            sh, p2p = mesh_share(ds, dof)
            print(f"te={te} {dof}: mesh-order share {sh:.3f}, p2p {p2p:.3e} m/s")
