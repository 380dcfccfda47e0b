"""Experiment: seed 004 §8.2 "The transverse signals show that the steady state ... within 0.3 s"
(Figs 8-1 sun, 8-13 carrier: displacement vs time, case 1 from rest). Settling time of the
transverse displacement magnitude |(x, y)| for several bands (fraction of its start-up peak
above the steady level)."""
from __future__ import annotations

import sys

import numpy as np

sys.path.append("tests")
from validation.seed004._reclaimer import R_C, run  # noqa: E402

RPM = 60 / (2 * np.pi)


def edit(cpb, load):
    def f(d):
        sim = d["planetary_dynamics"]["simulation"]
        sim["initial_speed_rpm"] = {}
        if not load:
            del sim["wheel_load"]
        elif load == "rated":  # ipdata(41) = 1, "simplified high torque": T = T_fl G at n_op
            sim["wheel_load"]["control_ratio"] = 1.0
        d["planetary_dynamics"]["stages"][0]["planet_bearing_damping_ns_per_m"] = cpb
    return f


def settle(t, y, band, t_ss=1.5):
    ss = y[t > t_ss]
    lo, hi = ss.min(), ss.max()
    peak = np.abs(y).max()
    tol = band * peak
    out = np.flatnonzero((y > hi + tol) | (y < lo - tol))
    return t[out[-1] + 1] if out.size else 0.0, peak, lo, hi


if __name__ == "__main__":
    for cpb in (0.0, 1e10):
        for load in (False, True, "rated"):
            _, ds = run([], 2.0, edit=edit(cpb, load))
            t = ds.time.values
            res = []
            for b in ("sun", "carrier", "ring"):
                mag = np.hypot(ds.q.sel(dof=f"{b}.x").values, ds.q.sel(dof=f"{b}.y").values)
                ts = [settle(t, mag, band)[0] for band in (0.05, 0.02, 0.0)]
                _, peak, lo, hi = settle(t, mag, 0)
                res.append(f"{b}: peak {peak*1e6:.1f} µm ss [{lo*1e6:.2f},{hi*1e6:.2f}] "
                           f"t5%={ts[0]:.3f} t2%={ts[1]:.3f} t0={ts[2]:.3f}")
            rpm = ds.v.sel(dof="carrier.u").values / R_C * RPM
            fin = rpm[t > 1.5].mean()
            sp = [t[np.flatnonzero(np.abs(rpm - fin) > b * fin)[-1] + 1] for b in (0.05, 0.02)]
            ring_u = ds.q.sel(dof="ring.u").values
            print("   ring u mean 1.5-2 s (mm)", ring_u[t > 1.5].mean() * 1e3)
            print(f"cpb={cpb:g} load={load}: speed t5%={sp[0]:.3f} t2%={sp[1]:.3f}; "
                  f"ring u peak {np.abs(ring_u).max()*1e3:.3f} mm")
            for r in res:
                print("   ", r)
