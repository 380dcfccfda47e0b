"""Seed 003 (Hammami 2015) Model B (12-DOF torsional, eqs 4.2-4.6): which reading of the
printed equations and Table 3.1 gives the simulated run-up lines of 25 Hz and 144 Hz (text of
Figs 4.28-4.29)? Independent numpy assembly of eqs 4.2, 4.4/4.5, 4.6 (q order of eq 4.9).

Readings (notes §5.1 items 2, 5 and §2.4 errata): rotational mass I/r² (eq 3.3) or I/r (eq 4.2
as printed); ring supports as corrected (test ring 7.9e6, reaction ring 0) or as printed in
eq 4.6 (swapped); support and shaft stiffnesses in N·m/rad (÷r²) or directly in N/m on u;
carrier radius 81.65 / 76.73 / 57.55 / 28.78 mm. Run:
PYTHONPATH=src python experiments/seed003_model_b_readings.py
"""
from __future__ import annotations

import itertools

import numpy as np
from scipy.linalg import eigh

RS, RP, RR = 0.03069, 0.04604, 0.12469
MS, MP, MR, MC = 0.485, 1.225, 28.1, 3.643
IS, IP, IR, IC = 356e-6, 2045e-6, 0.697767, 0.021502
KSM, KRM = 4.46e8, 6.28e8
KS_SHAFT, KC_SHAFT, K_RING = 3.73e4, 8.38e5, 7.9e6


def model_b(mass="I/r2", placement="corrected", support="Nm/rad", shaft="Nm/rad", rc=0.08165,
            ksm=KSM, krm=KRM):
    """(M, K) of eqs 4.2-4.6, q = (c, r, s, p1, p2, p3) reaction then test."""
    p = 2 if mass == "I/r2" else 1

    def rot(i, r):
        return i / r**p

    m_set = [rot(IC, rc) + 3 * MP, rot(IR, RR), rot(IS, RS)] + [rot(IP, RP)] * 3
    M = np.diag(m_set * 2)
    K = np.zeros((12, 12))
    for o in (0, 6):
        for n in range(3):
            for k, a in ((ksm, {o + 2: 1, o + 3 + n: 1, o: -1}),   # δ_sn = u_s + u_n − u_c
                         (krm, {o + 1: 1, o + 3 + n: -1, o: -1})):  # δ_rn = u_r − u_n − u_c
                v = np.zeros(12)
                for i, c in a.items():
                    v[i] = c
                K += k * np.outer(v, v)
    conv_s = RS**2 if shaft == "Nm/rad" else 1.0
    conv_c = rc**2 if shaft == "Nm/rad" else 1.0
    for i, j, k in ((0, 6, KC_SHAFT / conv_c), (2, 8, KS_SHAFT / conv_s)):
        K[np.ix_([i, j], [i, j])] += k * np.array([[1, -1], [-1, 1]])
    ks = K_RING / (RR**2 if support == "Nm/rad" else 1.0)
    K[7 if placement == "corrected" else 1, 7 if placement == "corrected" else 1] += ks
    return M, K


def freqs(M, K):
    w2 = eigh(K, M, eigvals_only=True)
    return np.sqrt(np.clip(w2, 0, None)) / (2 * np.pi)


if __name__ == "__main__":
    np.set_printoptions(precision=1, suppress=True, linewidth=150)
    grid = dict(mass=["I/r2", "I/r"], placement=["corrected", "printed"],
                support=["Nm/rad", "N/m"], shaft=["Nm/rad", "N/m"],
                rc=[0.08165, 0.07673, 0.05755, 0.028775])
    rows = []
    for vals in itertools.product(*grid.values()):
        kw = dict(zip(grid, vals, strict=True))
        f = freqs(*model_b(**kw))
        low = f[(f > 0.5) & (f < 1000)]
        d25 = np.min(np.abs(np.log(f[f > 0.5] / 25)))
        d144 = np.min(np.abs(np.log(f[f > 0.5] / 144)))
        rows.append((max(d25, d144), kw, low))
    rows.sort(key=lambda r: r[0])
    for s, kw, low in rows[:10]:
        print(f"{s:.3f} {kw}\n      {low}")
    print("corrected / Nm/rad / Nm/rad / I/r2 / 81.65 mm:",
          freqs(*model_b())[:6])
