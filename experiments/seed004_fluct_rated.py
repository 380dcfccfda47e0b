"""Experiment: case 1 / case 2 carrier speed fluctuation under the rated-torque load that the
thesis's own Fig 8-8 number implies (ipdata(41) = 1), with and without the Table 7-1 planet
bearing damping; from rest (case 1, as Fig 8-28) and from the nominal speed."""
from __future__ import annotations

import sys

import numpy as np

sys.path.append("tests")
from validation.seed004._reclaimer import R_C, ZR, run  # noqa: E402

RPM = 60 / (2 * np.pi)


def edit(case, cpb, rest, te=False):
    def f(d):
        sim = d["planetary_dynamics"]["simulation"]
        st = d["planetary_dynamics"]["stages"][0]
        if rest:
            sim["initial_speed_rpm"] = {}
        else:
            sim["initial_speed_rpm"] = {"motor": 952.5, "sun": 5.8885 * 5.3684}
        sim["wheel_load"]["control_ratio"] = 1.0
        st["planet_bearing_damping_ns_per_m"] = cpb
        if case == 2:
            st["carrier"]["mass_kg"], st["carrier"]["inertia_kgm2"] = 26431.0, 92926.0
    return f


if __name__ == "__main__":
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 3.0
    for cpb in (0.0, 1e10):
        for rest in (True, False):
            out = []
            for case in (1, 2):
                _, ds = run([], t_end, edit=edit(case, cpb, rest))
                t = ds.time.values
                rpm = ds.v.sel(dof="carrier.u").values / R_C * RPM
                s = t > t_end - 1
                x = ZR * ds.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
                # order-3 line and detrended p2p against the carrier angle
                n = int(np.floor(x[s][-1] - x[s][0]))
                g = x[s][0] + np.arange(n * 64) / 64
                y = np.interp(g, x[s], rpm[s])
                y = y - np.polyval(np.polyfit(g, y, 1), g)
                sp = np.abs(np.fft.rfft(y)) * 2 / y.size
                out.append((np.ptp(rpm[s]), np.ptp(y), rpm[s].mean(), sp[n], sp[3 * n]))
            print(f"cpb={cpb:g} rest={rest}: " + " | ".join(
                f"case{c+1} p2p {o[0]:.4f} detr {o[1]:.4f} mean {o[2]:.3f} ord1 {o[3]:.1e} "
                f"ord3 {o[4]:.1e}" for c, o in enumerate(out))
                + f" | ratio {out[0][1]/out[1][1]:.2f}")
