"""Experiment: what sets the place of the carrier torsional signal in the seed 004 ch. 9 ranking.

Metrics: ``time`` = the old test's (fault − healthy at equal time, carrier-frame x/y);
``angle`` = fault − healthy at equal carrier angle (mesh cycles, as the thesis's "shaft
position"), central x/y and planet x*/y* in the fixed frame (the thesis's coordinates, planet
position about the sun centre, orbit included)."""
from __future__ import annotations

import sys
import time

import numpy as np
from scipy.signal import detrend

sys.path.append("tests")
from validation.seed004._reclaimer import R_C, ZR, run  # noqa: E402

SIG = {"xs": "sun.x", "ys": "sun.y", "us": "sun.u", "xr": "ring.x", "yr": "ring.y",
       "ur": "ring.u", "xc": "carrier.x", "yc": "carrier.y", "uc": "carrier.u",
       "xp": "planet1.zeta", "yp": "planet1.eta", "up": "planet1.u"}
T_END = 8.0


def fixed_frame(ds):
    """Seed-style signals (velocities, m/s): fixed-frame x, y of sun, ring, carrier; planet 1
    x*, y* about the sun centre (orbit r_c included); u rates as they are."""
    t = ds.time.values
    th = ds.q.sel(dof="carrier.u").values / R_C
    c, s = np.cos(th), np.sin(th)
    out = {}
    for b, k in (("sun", "s"), ("ring", "r"), ("carrier", "c")):
        x, y = ds.q.sel(dof=f"{b}.x").values, ds.q.sel(dof=f"{b}.y").values
        out["x" + k] = np.gradient(x * c - y * s, t)
        out["y" + k] = np.gradient(x * s + y * c, t)
    z, e = ds.q.sel(dof="planet1.zeta").values, ds.q.sel(dof="planet1.eta").values
    rad = R_C + z
    out["xp"] = np.gradient(rad * c - e * s, t)
    out["yp"] = np.gradient(rad * s + e * c, t)
    for k in ("us", "ur", "uc", "up"):
        out[k] = ds.v.sel(dof=SIG[k]).values
    return out


def scores_time(h, c, tmin=2.0):
    sel = h.time.values > tmin
    return {k: (np.ptp(detrend(c.v.sel(dof=d).values[sel] - h.v.sel(dof=d).values[sel])),
                np.ptp(detrend(h.v.sel(dof=d).values[sel]))) for k, d in SIG.items()}


def scores_angle(h, c, tmin=2.0, fixed=True):
    xh = ZR * h.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
    xc = ZR * c.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
    x0 = max(np.interp(tmin, h.time.values, xh), np.interp(tmin, c.time.values, xc))
    x1 = min(xh[-1], xc[-1])
    grid = np.linspace(x0, x1, 20000)
    sh = fixed_frame(h) if fixed else {k: h.v.sel(dof=d).values for k, d in SIG.items()}
    sc = fixed_frame(c) if fixed else {k: c.v.sel(dof=d).values for k, d in SIG.items()}
    out = {}
    for k in SIG:
        a = np.interp(grid, xh, sh[k])
        b = np.interp(grid, xc, sc[k])
        out[k] = (np.ptp(detrend(b - a)), np.ptp(detrend(a)))
    return out


def show(label, sc):
    r = sorted(sc, key=lambda k: -sc[k][0] / sc[k][1])
    print(f"{label:32s}", " ".join(f"{k}:{sc[k][0]/sc[k][1]:.3g}" for k in r))


def case2(d):
    d["planetary_dynamics"]["simulation"]["wheel_load"]["inertia_schedule"] = True


if __name__ == "__main__":
    variants = {"default": None, "case2": case2}
    faults = {"sun_crack": [{"kind": "crack", "gear": "sun", "crack_fraction": 0.4}],
              "planet_crack": [{"kind": "crack", "gear": "planet", "crack_fraction": 0.4}]}
    for vname, ed in variants.items():
        t0 = time.time()
        _, h = run([], T_END, edit=ed)
        for fname, f in faults.items():
            _, c = run(f, T_END, edit=ed)
            show(f"{vname} {fname} time", scores_time(h, c))
            show(f"{vname} {fname} angle rot", scores_angle(h, c, fixed=False))
            show(f"{vname} {fname} angle fixed", scores_angle(h, c))
        print(f"  ({time.time()-t0:.1f} s)")
