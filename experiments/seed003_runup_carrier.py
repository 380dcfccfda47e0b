"""Seed 003 (Hammami 2015) Figs 4.28-4.29: lines in the STFT of the test-carrier acceleration
during a simulated run-up (thesis: 25 Hz and 144 Hz), torsional Model B (12-DOF example), with
the test-ring support read as printed in Table 3.1 (7.9e6 N/m on u = r θ) or as N·m/rad.
Prints the share of STFT frames in which each bin is a spectral peak, for bins that are peaks in
≥ 50 % of the frames. Run: PYTHONPATH=src python experiments/seed003_runup_carrier.py [36]
"""
from __future__ import annotations

import sys
import time

import numpy as np
from scipy.signal import find_peaks, stft

sys.path.insert(0, "tests/validation/seed003")
sys.path.insert(0, ".")
from tests.validation.seed003._bench import raw, run  # noqa: E402

RR = 0.12469
DT, T_UP, RPM0, RPM1 = 5e-5, 1.0, 100.0, 1498.5


def config(name: str, unit: str) -> dict:
    d = raw(name)
    for st in d["planetary_dynamics"]["stages"]:
        if st["stage"] == "test":
            k = 7.9e6 * RR**2 if unit == "N/m" else 7.9e6
            st["ring"]["torsional_support_nm_per_rad"] = k
    sim = d["planetary_dynamics"]["simulation"]
    body = sim["speed_controls"][0]["body"]
    sim["initial_speed_rpm"] = {body: RPM0}
    sim["speed_controls"][0]["profile_rpm"] = [[0.0, RPM0], [T_UP, RPM1]]
    sim["torques"] = [{"body": "reaction.ring", "torque_nm": 100.0}]
    sim["t_end_s"] = T_UP
    return d


def lines(ds, dof: str) -> list[tuple[float, float]]:
    acc = np.gradient(ds.v.sel(dof=dof).values, DT)
    f, _, z = stft(acc, fs=1 / DT, nperseg=4096, noverlap=3072)
    a = np.abs(z)
    hits = np.zeros(f.size)
    for j in range(a.shape[1]):
        pk, _ = find_peaks(a[:, j], prominence=0.05 * a[:, j].max())
        hits[pk] += 1
    share = hits / a.shape[1]
    keep = (share >= 0.5) & (f < 1000)
    return [(round(float(x), 1), round(float(s), 2)) for x, s in zip(f[keep], share[keep],
                                                                      strict=True)]


if __name__ == "__main__":
    name = ("planetary_bench_36dof.toml" if sys.argv[1:] == ["36"]
            else "planetary_bench_12dof.toml")
    for unit in ("N/m", "Nm/rad"):
        t0 = time.time()
        _, _, ds = run(config(name, unit), T_UP, DT)
        print(name, unit, f"{time.time() - t0:.0f} s")
        for dof in ("test.carrier.u", "test.ring.u"):
            print("  ", dof, lines(ds, dof))
