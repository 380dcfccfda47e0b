"""Experiment: what fluctuates in the case-1 carrier speed (seed 004 §8.3)."""
from __future__ import annotations

import sys

import numpy as np

sys.path.append("tests")
from seed004_fluct import RPM, edit  # noqa: E402

from validation.seed004._reclaimer import R_C, run  # noqa: E402

if __name__ == "__main__":
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 2.0
    rest = len(sys.argv) > 2 and sys.argv[2] == "rest"
    beta = float(sys.argv[3]) if len(sys.argv) > 3 else None
    _, ds = run([], t_end, edit=edit(1, beta, rest=rest))
    t = ds.time.values
    rpm = ds.v.sel(dof="carrier.u").values / R_C * RPM
    edges = [0, .1, .2, .3, .5, 1, 1.5, 2, 3, 4]
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        s = (t >= a) & (t < b)
        if s.any():
            print(f"{a:.1f}-{b:.1f} s: mean {rpm[s].mean():.3f} p2p {np.ptp(rpm[s]):.4f}")
    s = t > t_end / 2
    x = rpm[s] - rpm[s].mean()
    f = np.fft.rfftfreq(x.size, t[1] - t[0])
    a = np.abs(np.fft.rfft(x * np.hanning(x.size))) * 4 / x.size
    top = np.argsort(a)[-8:][::-1]
    print("top lines (Hz, rpm):", [(round(f[i], 2), round(a[i], 4)) for i in top])
    mot = ds.v.sel(dof="motor.theta").values * RPM
    print("motor rpm end", mot[-1], "sun rpm", ds.v.sel(dof="sun.u").values[-1] / 0.1428333 * RPM)
