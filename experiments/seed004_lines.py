"""Experiment: mesh-order lines of the carrier and sun torsional speed (seed 004 §8.2: 83 pulses
per carrier revolution on the carrier, 57 = 3·19 per sun revolution on the sun), and the
case-1 (arm + empty-wheel load) / case-2 (wheel inertia) fluctuation with the Table 7-1 planet
bearing damping."""
from __future__ import annotations

import sys

import numpy as np

sys.path.append("tests")
from validation.seed004._reclaimer import R_C, ZR, run  # noqa: E402

RPM = 60 / (2 * np.pi)


def edit(cpb, wheel):
    def f(d):
        d["planetary_dynamics"]["stages"][0]["planet_bearing_damping_ns_per_m"] = cpb
        if wheel:
            d["planetary_dynamics"]["simulation"]["wheel_load"]["inertia_schedule"] = True
    return f


def orders(ds, dof, t0=2.0):
    """Amplitude (rpm) of mesh orders 1..4 (per mesh cycle X) of a torsional speed."""
    x = ZR * ds.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
    t = ds.time.values
    s = t > t0
    r = {"carrier.u": R_C, "sun.u": 0.1428333}[dof]
    w = ds.v.sel(dof=dof).values / r * RPM
    n_cyc = int(np.floor(x[s][-1] - x[s][0]))
    grid = x[s][0] + np.arange(n_cyc * 64) / 64
    y = np.interp(grid, x[s], w[s])
    y = y - np.polyval(np.polyfit(grid, y, 1), grid)
    sp = np.abs(np.fft.rfft(y)) * 2 / y.size
    return [sp[h * n_cyc] for h in (1, 2, 3, 4)], np.ptp(y)


if __name__ == "__main__":
    for cpb in (0.0, 1e10):
        for wheel in (False, True):
            _, ds = run([], 6.0, edit=edit(cpb, wheel))
            for dof in ("carrier.u", "sun.u"):
                a, p2p = orders(ds, dof)
                print(f"cpb={cpb:g} wheel={wheel} {dof}: orders 1-4 (rpm) "
                      + " ".join(f"{v:.2e}" for v in a) + f"  p2p {p2p:.2e} rpm")
