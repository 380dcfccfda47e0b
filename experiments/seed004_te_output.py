"""Experiment: seed 004 §8.3 case 3 vs case 2 ("the tooth mesh cycle becomes unclear and the
irregularity is increased"; "the torsional speed is slightly increased"). Case 2 = carrier +
wheel (Table 6-4) under the rated load implied by Fig 8-8 (ipdata(41) = 1), from the steady
speed; case 3 = case 2 + combined transmission error. Synchronous average of the sun torsional
speed over sun revolutions relative to the carrier (z_s = 19 mesh cycles, §8.2) and of the
carrier speed over 19 mesh cycles; share of the averaged signal's variance at integer mesh
orders."""
from __future__ import annotations

import sys

import numpy as np

sys.path.append("tests")
from validation.seed004._reclaimer import R_C, ZR, ZS, run  # noqa: E402

T0 = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0


def case2(cpb=0.0):
    def f(d):
        sim = d["planetary_dynamics"]["simulation"]
        st = d["planetary_dynamics"]["stages"][0]
        sim["initial_speed_rpm"] = {"motor": 952.5, "sun": 5.8885 * 5.3684}
        sim["wheel_load"]["control_ratio"] = 1.0
        st["carrier"]["mass_kg"], st["carrier"]["inertia_kgm2"] = 26431.0, 92926.0
        st["planet_bearing_damping_ns_per_m"] = cpb
    return f


def averaged(ds, dof, period=ZS, spc=64, t0=T0):
    t = ds.time.values
    x = ZR * ds.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
    s = t > t0
    x0 = np.ceil(x[s][0])
    n_rev = int((x[s][-1] - x0) // period)
    g = x0 + np.arange(n_rev * period * spc) / spc
    y = np.interp(g, x[s], ds.v.sel(dof=dof).values[s])
    return y.reshape(n_rev, -1).mean(0), n_rev, y.mean()


def mesh_share(avg, period=ZS):
    p = np.abs(np.fft.rfft(avg - avg.mean())) ** 2
    return p[period::period].sum() / p.sum()


if __name__ == "__main__":
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 8.0
    for cpb in (0.0, 1e10):
        for te in (False, True):
            _, ds = run([], t_end, te=te, edit=case2(cpb))
            for dof in ("sun.u", "carrier.u"):
                avg, n, mean = averaged(ds, dof)
                print(f"cpb={cpb:g} te={te} {dof}: {n} revs, mesh share {mesh_share(avg):.3f}, "
                      f"avg p2p {np.ptp(avg):.3e}, mean {mean:.6f} m/s")
