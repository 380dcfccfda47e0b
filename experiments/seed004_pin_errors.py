"""Experiment: the thesis code's planet position errors (ipdata(301-303) = 0.03, 0.05, 0.08°,
D_tcp = r_cp·angle, r_cp = r_c + 0.1 mm) as tangential pin errors, case 1 under the rated load:
do they bring the order-1 mesh line (83 pulses per carrier revolution, Fig 8-15) and a ≈ 1 rpm
fluctuation to the carrier speed?"""
from __future__ import annotations

import sys

import numpy as np

sys.path.append("tests")
from validation.seed004._reclaimer import R_C, ZR, run  # noqa: E402

RPM = 60 / (2 * np.pi)
R_CP = R_C + 1e-4
PIN = [R_CP * np.radians(a) for a in (0.03, 0.05, 0.08)]


def edit(cpb, pins):
    def f(d):
        sim = d["planetary_dynamics"]["simulation"]
        st = d["planetary_dynamics"]["stages"][0]
        sim["initial_speed_rpm"] = {"motor": 952.5, "sun": 5.8885 * 5.3684}
        sim["wheel_load"]["control_ratio"] = 1.0
        st["planet_bearing_damping_ns_per_m"] = cpb
        if pins:
            st["pin_errors_m"] = PIN
    return f


if __name__ == "__main__":
    for cpb in (0.0, 1e10):
        for pins in (False, True):
            _, ds = run([], 4.0, edit=edit(cpb, pins))
            t = ds.time.values
            s = t > 2.0
            rpm = ds.v.sel(dof="carrier.u").values / R_C * RPM
            x = ZR * ds.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
            n = int(np.floor(x[s][-1] - x[s][0]))
            g = x[s][0] + np.arange(n * 64) / 64
            y = np.interp(g, x[s], rpm[s])
            y = y - np.polyval(np.polyfit(g, y, 1), g)
            sp = np.abs(np.fft.rfft(y)) * 2 / y.size
            lsr = ds["lsr_planetary"].values[s].mean(0) if "lsr_planetary" in ds else None
            print(f"cpb={cpb:g} pins={pins}: p2p {np.ptp(rpm[s]):.4f} rpm, order 1 {sp[n]:.2e}, "
                  f"order 3 {sp[3*n]:.2e} rpm; load sharing {np.round(lsr, 3)}")
