"""Exact (exponential, modal) time integration of a linear rotor at constant speed.

For a transmission without gear meshes or Hertzian bearings, turning at constant speed Ω (no
drive or load torque), the lateral motion obeys the linear time-invariant system

    M q̈ + (C + Σ_s Ω_s G_s) q̇ + K q = F(t),   F(t) = Σ_c Re(F̂_c e^{iω_c t}),

the loads being unbalances (m e Ω² rotating at Ω) and external loads whose time law (f) and
angle law (order n) give ω = 2π f + n Ω. In state space x = (q, q̇), ẋ = A x + B F with
A = V Λ V⁻¹ (complex modes, Friswell et al. 2010, §3.7), every modal coordinate ξ = V⁻¹ x
advances over a step h exactly (variation of constants; the exponential integrator of
Hochbruck & Ostermann, *Acta Numerica* 19, 2010, exact for these loads):

    ξ_k(t + h) = e^{λ_k h} ξ_k(t) + Σ_c ½ [(V⁻¹B F̂_c)_k φ(λ_k, iω_c) e^{iω_c t}
                                          + (V⁻¹B F̂_c*)_k φ(λ_k, −iω_c) e^{−iω_c t}],
    φ(λ, μ) = (e^{μ h} − e^{λ h})/(μ − λ)   (h e^{λ h} when μ = λ).

The step then only sets the output sampling; the cost per step is O(2n × loads) (diagonal
modal update), outputs are rebuilt on the recorded DOFs only. Axial and torsional DOFs must
be uncoupled from the lateral ones (true for Timoshenko shafts, discs, lateral supports) and
carry no load: they move rigidly (θz = θz₀ + Ω t). A defective or ill-conditioned modal basis
(free-free lateral motion, cond V > 1e10) is refused (use Newmark).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: DOF positions (in the 6 of a node) of the lateral motion x, y, θx, θy.
LATERAL = (0, 1, 3, 4)
MAX_COND = 1e10


def lateral_split(n: int) -> tuple[np.ndarray, np.ndarray]:
    """(lateral DOFs, axial + torsional DOFs) of ``n`` FE DOFs."""
    j = np.arange(n)
    lat = np.isin(j % 6, LATERAL)
    return j[lat], j[~lat]


def uncoupled(mats: list[np.ndarray], lat: np.ndarray, rest: np.ndarray) -> bool:
    """True when no matrix couples the lateral DOFs with the others."""
    return all(not np.any(A[np.ix_(lat, rest)]) and not np.any(A[np.ix_(rest, lat)])
               for A in mats)


def modal_basis(M: np.ndarray, K: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                                        np.ndarray, float]:
    """(λ, V, V⁻¹, cond V) of A = [[0, I], [−M⁻¹K, −M⁻¹C]]."""
    from scipy.linalg import eig, solve

    n = M.shape[0]
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -solve(M, K)
    A[n:, n:] = -solve(M, C)
    lam, V = eig(A)
    cond = float(np.linalg.cond(V))
    Vi = np.linalg.inv(V) if math.isfinite(cond) and cond < 1e300 else np.full_like(V, np.nan)
    return lam, V, Vi, cond


def phi(lam: np.ndarray, mu: complex, h: float) -> np.ndarray:
    """(e^{μh} − e^{λh})/(μ − λ), h e^{λh} where μ = λ (to rounding)."""
    d = mu - lam
    out = np.empty_like(lam)
    small = np.abs(d * h) < 1e-6
    e = np.exp(lam * h)
    # series of (e^{dh} − 1)/d for small dh, times e^{λh}
    out[small] = e[small] * h * (1 + 0.5 * d[small] * h + (d[small] * h) ** 2 / 6)
    big = ~small
    out[big] = (np.exp(mu * h) - e[big]) / d[big]
    return out


@njit(cache=True)
def run(xi, E, Gp, Gm, w, h, steps, Vrec, out, Vpow, fpow, pw):  # pragma: no cover
    """Advance ``steps`` steps of size h from t = 0: ξ ← E ξ + Σ_c (G⁺_c z_c + G⁻_c z̄_c),
    z_c = e^{iω_c t}; ``out[s]`` = Re(Vrec ξ) at step s (s = 0 … steps). ``pw`` receives
    Σ h (P(t) + P(t+h))/2 of the load power P = Σ_j Re(Vpow ξ)_j F_j(t) (``fpow``: (loads, c)
    complex amplitudes of the loaded DOFs per component)."""
    nc = w.size
    nk = xi.size
    nr = Vrec.shape[0]
    npow = Vpow.shape[0]
    for r in range(nr):
        acc = 0.0
        for k in range(nk):
            acc += (Vrec[r, k] * xi[k]).real
        out[0, r] = acc
    p0 = 0.0
    for r in range(npow):
        vr = 0.0
        for k in range(nk):
            vr += (Vpow[r, k] * xi[k]).real
        fr = 0.0
        for c in range(nc):
            fr += fpow[r, c].real
        p0 += vr * fr
    work = 0.0
    z = np.empty(nc, np.complex128)
    for s in range(steps):
        t = s * h
        for c in range(nc):
            z[c] = complex(math.cos(w[c] * t), math.sin(w[c] * t))
        for k in range(nk):
            acc = E[k] * xi[k]
            for c in range(nc):
                acc += Gp[c, k] * z[c] + Gm[c, k] * z[c].conjugate()
            xi[k] = acc
        for r in range(nr):
            acc = 0.0
            for k in range(nk):
                acc += (Vrec[r, k] * xi[k]).real
            out[s + 1, r] = acc
        t1 = t + h
        p1 = 0.0
        for r in range(npow):
            vr = 0.0
            for k in range(nk):
                vr += (Vpow[r, k] * xi[k]).real
            fr = 0.0
            for c in range(nc):
                fr += (fpow[r, c] * complex(math.cos(w[c] * t1), math.sin(w[c] * t1))).real
            p1 += vr * fr
        work += 0.5 * h * (p0 + p1)
        p0 = p1
    pw[0] = work
