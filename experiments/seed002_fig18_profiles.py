"""Seed 002 (Thibault et al. 2024) Fig 18: dynamic (FE run, low-speed shaft IAS) against
quasi-static (PE table ΔSTE pulse) ratio spall/crack25 of the fault-induced integer-order
amplitudes, orders 1-60. The fault-induced amplitude at order k is |X_fault(k) − X_healthy(k)|
(complex, same record length; removes the healthy content). Three FE runs (≈ 5-30 s each).
Run: PYTHONPATH=src python experiments/seed002_fig18_profiles.py
"""
from __future__ import annotations

import sys
import time

import numpy as np

sys.path.insert(0, ".")
sys.path.insert(0, "experiments")
from seed002_spall_vs_crack import NPC, table  # noqa: E402
from tests.validation.seed002._runs import PPR, detrended  # noqa: E402


def induced(case: str, orders: np.ndarray) -> np.ndarray:
    x, h = detrended(case), detrended("healthy")
    w = np.hanning(x.size)
    nrev = x.size / PPR
    xf, hf = np.fft.rfft(x * w), np.fft.rfft(h * w)
    idx = np.round(orders * nrev).astype(int)
    d = np.abs(xf - hf)
    return np.array([d[i - 1:i + 2].max() for i in idx]) * 2 / w.sum()


def static_pulse(case: str, orders: np.ndarray) -> np.ndarray:
    """|Fourier coefficient| at shaft order k of ΔSTE(θ) over one wheel revolution."""
    g, h = table("healthy")
    _, t = table(case)
    f = 100.0 / g.base_radius[1]
    d = f / t.total - f / h.total
    n_rev = 55 * NPC  # samples per wheel revolution; the hunting table spans 42 revolutions
    d = d[: (d.size // n_rev) * n_rev].reshape(-1, n_rev).mean(0)
    c = np.fft.rfft(d) / n_rev
    return np.abs(c[orders])


if __name__ == "__main__":
    orders = np.arange(1, 61)
    t0 = time.time()
    dyn = induced("gear_spall", orders) / induced("crack25", orders)
    print(f"FE runs {time.time() - t0:.0f} s")
    qs = static_pulse("gear_spall", orders) / static_pulse("crack25", orders)
    np.set_printoptions(precision=2, suppress=True, linewidth=150)
    for lo, hi in ((1, 4), (4, 20), (20, 38), (38, 55), (55, 61)):
        s = slice(lo - 1, hi - 1)
        print(f"orders {lo}-{hi - 1}: spall/crack25 dynamic median {np.median(dyn[s]):6.2f}, "
              f"quasi-static median {np.median(qs[s]):6.2f}")
    print("dynamic", dyn)
    print("static ", qs)
