"""Experiment: case-1 / case-2 carrier speed fluctuation vs damping (seed 004 §8.3)."""
from __future__ import annotations

import sys
import time

import numpy as np

sys.path.append("tests")
from validation.seed004._reclaimer import R_C, run  # noqa: E402

RPM = 60 / (2 * np.pi)


def edit(case, beta=None, cpb=None, rest=False):
    def f(d):
        sim = d["planetary_dynamics"]["simulation"]
        if rest:
            sim["initial_speed_rpm"] = {}
        if case == 1:
            del sim["wheel_load"]
        else:
            sim["wheel_load"]["schedule"] = True
            sim["wheel_load"]["inertia_schedule"] = True
        if beta is not None:
            sim["rayleigh_beta"] = beta
        if cpb is not None:
            d["planetary_dynamics"]["stages"][0]["planet_bearing_damping_ns_per_m"] = cpb
    return f


if __name__ == "__main__":
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 3.0
    for beta, cpb in ((1e-5, None), (0.0, None), (1e-5, 1e4), (1e-5, 1e10), (0.0, 1e10)):
        res = []
        for case in (1, 2):
            t0 = time.time()
            _, ds = run([], t_end, edit=edit(case, beta, cpb))
            t = ds.time.values
            rpm = ds.v.sel(dof="carrier.u").values / R_C * RPM
            sel = t > t_end - 1.0
            res.append((np.ptp(rpm[sel]), rpm[sel].mean(), time.time() - t0))
        print(f"beta={beta:g} cpb={cpb}: case1 p2p {res[0][0]:.3f} rpm (mean {res[0][1]:.3f}), "
              f"case2 p2p {res[1][0]:.4f} (mean {res[1][1]:.3f}), ratio {res[0][0]/res[1][0]:.2f}"
              f"  [{res[0][2]:.1f}+{res[1][2]:.1f} s]")
