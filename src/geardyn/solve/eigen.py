"""Generic modal solver for every model on the assembly core (seed 003 ch. 3, SI units).

Model-free functions on matrices, deflection rows and element blocks; the planetary
(:mod:`geardyn.solve.modal`), mechanism (:mod:`geardyn.models.core.modal`) and FE
(:mod:`geardyn.models.transmission.modal`) modal analyses are thin wrappers that add their
own mode classification.

* :func:`eigenmodes` — ω² M φ = K φ (seed 003 eq 3.27): frequencies (Hz, ascending),
  mass-normalised shapes (φᵀ M φ = I; zeros on ``fixed`` DOFs), degenerate groups and
  multiplicities (:func:`degenerate_groups`, one rule for every model), rigid-body modes
  (below ``zero_hz``, reported as exactly 0 Hz).
* Modal energies for a unit modal amplitude: kinetic per DOF Ec_k = ½ ω² φ_k (Mφ)_k
  (seed 003 eq 3.29, :func:`kinetic_energy`), strain per rank-one element
  Ep_e = ½ k_e (a_eᵀφ)² (eq 3.28, :func:`strain_rank_one`) and per element block
  Ep_e = ½ φ_eᵀ K_e φ_e (:func:`strain_blocks`); :func:`assembly_strain` takes both from an
  :class:`~geardyn.models.core.assembly.Assembly`. For a mass-normalised mode each set of
  bins sums to ½ ω² when the elements make up K.
* :func:`campbell` — frequencies of the quadratic eigenproblem
  M q̈ + Σ_c Ω_c G_c q̇ + (K − Σ_c Ω_c² K_Ω,c) q = 0 (seed 003 eq 3.1, homogeneous part) with
  Ω_c = rate_c × speed, solved in state-space form; sorted per speed, or tracked along the
  speeds by the continuity of the mode shapes (``track=True``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.linalg as sla
from scipy.optimize import linear_sum_assignment

from geardyn.errors import InputError

if TYPE_CHECKING:
    from geardyn.models.core.assembly import Assembly

#: A rotating frame's terms for :func:`campbell`: (rate, G, K_Ω) with Ω = rate × speed;
#: G or K_Ω may be None (absent).
FrameTerm = tuple[float, "np.ndarray | None", "np.ndarray | None"]


@dataclass(frozen=True)
class Eigenmodes:
    """Result of :func:`eigenmodes`."""

    freq_hz: np.ndarray  # (m,) Hz, ascending; rigid-body modes exactly 0
    shapes: np.ndarray  # (n, m) mass-normalised columns, zeros on fixed DOFs
    groups: list[list[int]]  # degenerate groups of mode indices
    multiplicity: np.ndarray  # (m,) size of each mode's group
    rigid: np.ndarray  # (m,) bool, frequency below zero_hz


def _square(name: str, a: np.ndarray, n: int | None = None) -> np.ndarray:
    a = np.asarray(a, float)
    if a.ndim != 2 or a.shape[0] != a.shape[1] or (n is not None and a.shape[0] != n):
        want = "square" if n is None else f"{n} × {n}"
        raise InputError(f"{name}: must be a {want} matrix, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name}: non-finite entries (NaN or inf)")
    return a


def degenerate_groups(freq_hz: np.ndarray, rtol: float = 1e-6, atol_hz: float = 1e-3
                      ) -> list[list[int]]:
    """Groups of consecutive modes with equal frequencies: mode j joins the group of mode i
    (the group's first) when |f_j − f_i| ≤ max(atol_hz, rtol |f_j|) (ascending ``freq_hz``)."""
    if rtol < 0 or atol_hz < 0 or not (np.isfinite(rtol) and np.isfinite(atol_hz)):
        raise InputError(f"rtol, atol_hz: must be finite and ≥ 0, got {rtol!r}, {atol_hz!r}")
    groups: list[list[int]] = []
    for i, f in enumerate(np.asarray(freq_hz, float)):
        if groups and abs(f - freq_hz[groups[-1][0]]) <= max(atol_hz, rtol * abs(f)):
            groups[-1].append(i)
        else:
            groups.append([i])
    return groups


def multiplicity(groups: Sequence[Sequence[int]], n: int) -> np.ndarray:
    """Per mode, the size of its degenerate group."""
    mult = np.ones(n, np.int64)
    for g in groups:
        mult[list(g)] = len(g)
    return mult


def eigenmodes(M: np.ndarray, K: np.ndarray, fixed: Sequence[int] | np.ndarray = (),
               zero_hz: float = 1e-2, rtol: float = 1e-6, atol_hz: float = 1e-3) -> Eigenmodes:
    """Undamped modes ω² M φ = K φ (seed 003 eq 3.27) with the DOFs ``fixed`` clamped.

    Frequencies f = √max(ω², 0)/2π in Hz, ascending; those below ``zero_hz`` are rigid-body
    modes and set to 0. Shapes are mass-normalised (φᵀ M φ = I), of full size n with zeros on
    the fixed DOFs. Degenerate groups follow :func:`degenerate_groups` (``rtol``, ``atol_hz``).
    """
    M = _square("M", M)
    K = _square("K", K, M.shape[0])
    n = M.shape[0]
    if not np.isfinite(zero_hz) or zero_hz < 0:
        raise InputError(f"zero_hz: must be finite and ≥ 0, got {zero_hz!r}")
    fixed = np.asarray(fixed, dtype=np.int64).ravel()
    if fixed.size and (fixed.min() < 0 or fixed.max() >= n):
        raise InputError(f"fixed: DOF indices must lie in [0, {n}), got {fixed.tolist()}")
    if fixed.size:
        free = np.setdiff1d(np.arange(n), fixed)
        w2, phi_free = sla.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)])
        phi = np.zeros((n, free.size))
        phi[free] = phi_free
    else:
        w2, phi = sla.eigh(K, M)
    freq = np.sqrt(np.clip(w2, 0.0, None)) / (2 * np.pi)
    rigid = freq < zero_hz
    freq[rigid] = 0.0
    groups = degenerate_groups(freq, rtol, atol_hz)
    return Eigenmodes(freq, phi, groups, multiplicity(groups, freq.size), rigid)


def participation(M: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Mass-weighted participation φ_k (Mφ)_k per (mode, DOF); rows sum to 1 for
    mass-normalised shapes."""
    return (shapes * (M @ shapes)).T


def kinetic_energy(M: np.ndarray, freq_hz: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Modal kinetic energy per DOF Ec_k = ½ ω² φ_k (Mφ)_k (seed 003 eq 3.29), (mode, DOF) in J
    for a unit modal amplitude."""
    w2 = (2 * np.pi * np.asarray(freq_hz, float)) ** 2
    return 0.5 * w2[:, None] * participation(M, shapes)


def strain_rank_one(shapes: np.ndarray, rows: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Modal strain energy of rank-one springs Ep_e = ½ k_e (a_eᵀφ)² (seed 003 eq 3.28),
    (mode, element) in J; ``rows``: deflection rows a_e (elements × n), ``k``: stiffnesses."""
    rows = np.asarray(rows, float).reshape(len(k), shapes.shape[0])
    return 0.5 * np.asarray(k, float)[None, :] * (rows @ shapes).T ** 2


def strain_blocks(shapes: np.ndarray, blocks: Sequence[tuple[np.ndarray, np.ndarray]]
                  ) -> np.ndarray:
    """Modal strain energy of element blocks Ep_e = ½ φ_eᵀ K_e φ_e (seed 003 eq 3.28 with an
    element matrix), (mode, element) in J; ``blocks``: (DOF indices, K_e) pairs."""
    out = np.zeros((shapes.shape[1], len(blocks)))
    for j, (dofs, ke) in enumerate(blocks):
        p = shapes[np.asarray(dofs)]
        out[:, j] = 0.5 * np.einsum("im,ij,jm->m", p, ke, p)
    return out


def assembly_strain(asm: Assembly, shapes: np.ndarray, kinds: Sequence[str] | None = None
                    ) -> tuple[list[str], list[str], np.ndarray]:
    """(names, kinds, strain (mode, element)) of the rank-one elements then the blocks with a
    stiffness matrix of ``asm`` (of ``kinds``, all if None); ``shapes`` on the assembly's DOFs."""
    ones = [e for e in asm.rank_one if kinds is None or e.kind in kinds]
    blocks = [b for b in asm.blocks if "K" in b.mats and (kinds is None or b.kind in kinds)]
    strain = np.hstack([
        strain_rank_one(shapes, np.array([e.a for e in ones]), np.array([e.k for e in ones])),
        strain_blocks(shapes, [(b.dofs, b.mats["K"]) for b in blocks]),
    ])
    return ([e.name for e in ones] + [b.name for b in blocks],
            [e.kind for e in ones] + [b.kind for b in blocks], strain)


def frame_terms(asm: Assembly, motion: np.ndarray) -> list[FrameTerm]:
    """:func:`campbell` terms of the rotating frames of ``asm``
    (:meth:`~geardyn.models.core.assembly.Assembly.frame_terms`) for the rigid-body motion
    ``motion`` (q̇ per unit reference speed): rate_c = r_c · motion."""
    motion = np.asarray(motion, float)
    if motion.shape != (asm.n,) or not np.all(np.isfinite(motion)):
        raise InputError(f"motion: must be {asm.n} finite values (one per DOF), got shape "
                         f"{motion.shape}")
    return [(float(r @ motion), g, k_om) for _name, r, g, k_om in asm.frame_terms()]


def _pair_frequencies(lam: np.ndarray) -> np.ndarray:
    """One frequency (Hz) per ± pair of state-space eigenvalues: eigenvalues of a real matrix
    come in conjugate pairs (real ones, e.g. the double 0 of a rigid mode, in an even number),
    so every other |Im λ| in ascending order."""
    return np.sort(np.abs(lam.imag))[::2] / (2 * np.pi)


def campbell(M: np.ndarray, K: np.ndarray, terms: Sequence[FrameTerm], speeds: np.ndarray,
             n_modes: int | None = None, min_hz: float | None = None,
             track: bool = False) -> np.ndarray:
    """Natural frequencies (Hz) against speed of M q̈ + Σ_c Ω_c G_c q̇ + (K − Σ_c Ω_c² K_Ω,c) q
    = 0 (seed 003 eq 3.1, homogeneous part), Ω_c = rate_c × speed (``terms``: (rate, G, K_Ω)
    per rotating frame or spinning shaft; ``speeds`` in rad/s of the reference).

    State-space form A = [[0, I], [−M⁻¹K_Ω, −M⁻¹G_Ω]]; one frequency per ± eigenvalue pair.
    Returns (speeds, n_modes), NaN where fewer: the ``n_modes`` lowest frequencies (those
    ≤ ``min_hz`` dropped, e.g. rigid-body modes) sorted per speed, or with ``track`` each
    column follows one mode from the first speed by the best match of the displacement parts
    of the eigenvectors (|xᵢᴴ M xⱼ|, assignment problem).
    """
    M = _square("M", M)
    n = M.shape[0]
    K = _square("K", K, n)
    speeds = np.atleast_1d(np.asarray(speeds, float))
    if speeds.ndim != 1 or not np.all(np.isfinite(speeds)):
        raise InputError("speeds: must be a 1-D array of finite speeds (rad/s)")
    terms = [(float(r), None if g is None else _square("G", g, n),
              None if ko is None else _square("K_omega", ko, n)) for r, g, ko in terms]
    if not all(np.isfinite(r) for r, _, _ in terms):
        raise InputError("terms: frame rates must be finite")
    n_modes = n_modes or n
    if n_modes < 1:
        raise InputError(f"n_modes: must be ≥ 1, got {n_modes}")
    out = np.full((speeds.size, n_modes), np.nan)
    minv = np.linalg.inv(M)
    prev = None
    for i, w in enumerate(speeds):
        g = np.zeros((n, n))
        ko = np.zeros((n, n))
        for rate, gc, kc in terms:
            om = rate * w
            if gc is not None:
                g += om * gc
            if kc is not None:
                ko += om * om * kc
        a = np.zeros((2 * n, 2 * n))
        a[:n, n:] = np.eye(n)
        a[n:, :n] = -minv @ (K - ko)
        a[n:, n:] = -minv @ g
        if not track:
            f = _pair_frequencies(np.linalg.eigvals(a))
            if min_hz is not None:
                f = f[f > min_hz]
            f = f[:n_modes]
            out[i, : f.size] = f
            continue
        lam, vec = np.linalg.eig(a)
        # the eigenvalue of each pair with Im λ > 0 (its conjugate carries the conjugate
        # shape: a forward whirl would look backward), and every other real one
        real = np.flatnonzero(lam.imag == 0.0)
        idx = np.concatenate([np.flatnonzero(lam.imag > 0.0),
                              real[np.argsort(lam[real].real)][::2]])
        idx = idx[np.argsort(lam.imag[idx], kind="stable")]
        f = lam.imag[idx] / (2 * np.pi)
        if min_hz is not None:
            keep = f > min_hz
            f, idx = f[keep], idx[keep]
        x = vec[:n, idx]
        x = x / np.sqrt(np.maximum(np.real(np.einsum("im,ij,jm->m", x.conj(), M, x)), 1e-300))
        if prev is None:
            f, x = f[:n_modes], x[:, :n_modes]
            out[i, : f.size] = f
        else:
            mac = np.abs(prev.conj().T @ M @ x)  # (previous column, candidate)
            rows, cols = linear_sum_assignment(-mac)
            f_new = np.full(prev.shape[1], np.nan)
            x_new = np.zeros_like(prev)
            f_new[rows] = f[cols]
            x_new[:, rows] = x[:, cols]
            out[i, : f_new.size] = f_new
            f, x = f_new, x_new
        prev = x
    return out


__all__ = ["Eigenmodes", "FrameTerm", "assembly_strain", "campbell", "degenerate_groups",
           "eigenmodes", "frame_terms", "kinetic_energy", "multiplicity", "participation",
           "strain_blocks", "strain_rank_one"]
