"""Experiment: is the thesis's case-1 "5 to 6 rpm" range (Fig 8-28) the carrier speed swing of
the bucket-wheel load schedule (loading ramp, periodic ore drops, ×10 overload: torqueOUT.m)
over one carrier revolution, and its "factor of 10" the smoothing by the wheel's inertia? Case 1:
carrier arm only, schedule on; case 2: carrier + wheel + buckets + ore (inertia schedule),
schedule on. From the no-load steady speed; carrier angle schedule in rad."""
from __future__ import annotations

import sys

import numpy as np

sys.path.append("tests")
from geardyn.operating import BucketWheelSchedule  # noqa: E402
from validation.seed004._reclaimer import R_C, run  # noqa: E402

RPM = 60 / (2 * np.pi)


def edit(case, cpb=0.0):
    def f(d):
        sim = d["planetary_dynamics"]["simulation"]
        sim["wheel_load"]["schedule"] = True
        sim["wheel_load"]["inertia_schedule"] = case == 2
        d["planetary_dynamics"]["stages"][0]["planet_bearing_damping_ns_per_m"] = cpb
    return f


if __name__ == "__main__":
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 26.0
    cpb = float(sys.argv[2]) if len(sys.argv) > 2 else 0.0
    pts = BucketWheelSchedule().points()
    print({k: round(v, 3) for k, v in pts.items()})
    res = {}
    for case in (1, 2):
        _, ds = run([], t_end, edit=edit(case, cpb))
        t = ds.time.values
        th = ds.q.sel(dof="carrier.u").values / R_C
        rpm = ds.v.sel(dof="carrier.u").values / R_C * RPM
        res[case] = (th, rpm)
        print(f"case {case}: carrier angle at end {th[-1]:.2f} rad ({th[-1]/2/np.pi:.2f} rev)")
        for a, b in (("0", "P44"), ("P44", "P45"), ("P45", "P49"), ("P49", "P50"),
                     ("P50", "P46"), ("P46", "P47")):
            lo = 0.0 if a == "0" else pts[a]
            s = (th >= lo) & (th < pts[b])
            if s.sum() > 10:
                print(f"   {a}-{b}: rpm min {rpm[s].min():.3f} max {rpm[s].max():.3f} "
                      f"range {np.ptp(rpm[s]):.3f}")
        # one carrier revolution windows
        for start in (0.0, pts["P44"], pts["P45"]):
            s = (th >= start) & (th < start + 2 * np.pi)
            if th[-1] >= start + 2 * np.pi:
                print(f"   1 rev from {start:.2f} rad: range {np.ptp(rpm[s]):.3f} rpm "
                      f"[{rpm[s].min():.3f}, {rpm[s].max():.3f}]")
