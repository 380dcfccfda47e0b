"""GTDT transfer path analysis (global / direct transmissibility, after Magrans and Guasch) in
the corrected, consistent form of ``shared/notes/seed003_notes.md`` §2.7 (seed 003 eqs
5.6-5.21; the printed (5.9)/(5.10) are inconsistent with (5.15)/(5.19)).

Conventions, per frequency (arrays carry a leading frequency axis ``(F, n, n)`` / ``(F, n)``):

* ``H`` receptance FRF matrix, ``Z = H⁻¹`` dynamic stiffness;
* global transmissibility ``T^G = H · diag(H_11…H_nn)⁻¹`` (``T^G_ij = H_ij/H_jj``), so that
  ``x = T^G x^ext`` with ``x^ext_j = H_jj f_j``;
* ``(T^G)⁻¹ = diag(H_ii) · Z`` (5.15); direct transmissibility ``T^D_ii = 1/(T^G⁻¹)_ii =
  1/(Z_ii H_ii)`` (5.14, 5.17) and ``T^D_ij = −T^D_ii (T^G⁻¹)_ij = −Z_ij/Z_ii`` (5.13, 5.16);
* ``x^ext = T^G⁻¹ x`` (5.19); reconstruction ``x = (T^D − Λ_TD) x + Λ_TD x^ext`` (5.21);
* path contributions to receiver i: ``T^D_ij x_j`` (j ≠ i) and ``T^D_ii x^ext_i``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geardyn.errors import InputError


@dataclass(frozen=True)
class GTDT:
    """Transmissibilities per frequency: ``global_`` = T^G, ``direct`` = T^D (diagonal holds
    T^D_ii), ``inv_global`` = (T^G)⁻¹; arrays of shape ``(F, n, n)``."""

    global_: np.ndarray
    direct: np.ndarray
    inv_global: np.ndarray


def _frf(H: np.ndarray) -> np.ndarray:
    h = np.asarray(H)
    if h.ndim == 2:
        h = h[None]
    if h.ndim != 3 or h.shape[1] != h.shape[2]:
        raise InputError(f"H: FRF matrix must have shape (n, n) or (F, n, n), got {h.shape}")
    if not np.all(np.isfinite(h)):
        raise InputError("H: FRF matrix contains NaN or infinite values")
    d = np.diagonal(h, axis1=1, axis2=2)
    if np.any(d == 0):
        raise InputError("H: a driving-point FRF H_ii is zero; transmissibilities undefined")
    return h.astype(complex)


def frf_from_mck(M: np.ndarray, C: np.ndarray, K: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """Receptance ``H(ω) = (K − ω²M + iωC)⁻¹`` [m/N or rad/(N·m)] at ``omega`` [rad/s];
    shape ``(F, n, n)``."""
    m, c, k = (np.asarray(a, dtype=float) for a in (M, C, K))
    if not (m.shape == c.shape == k.shape) or m.ndim != 2 or m.shape[0] != m.shape[1]:
        raise InputError("M, C, K: must be square matrices of the same shape")
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    z = k[None] - (w**2)[:, None, None] * m[None] + 1j * w[:, None, None] * c[None]
    try:
        return np.linalg.inv(z)
    except np.linalg.LinAlgError:
        raise InputError("omega: K − ω²M + iωC is singular at one of the frequencies") from None


def gtdt(H: np.ndarray) -> GTDT:
    """Global and direct transmissibilities from the FRF matrix (notes §2.7, eqs 5.8-5.18)."""
    h = _frf(H)
    d = np.diagonal(h, axis1=1, axis2=2)  # (F, n)
    tg = h / d[:, None, :]
    try:
        z = np.linalg.inv(h)
    except np.linalg.LinAlgError:
        raise InputError("H: FRF matrix is singular; T^G cannot be inverted") from None
    tg_inv = d[:, :, None] * z  # diag(H_ii) · Z   (5.15)
    tdii = 1.0 / np.diagonal(tg_inv, axis1=1, axis2=2)  # (5.17)
    td = -tdii[:, :, None] * tg_inv  # (5.16), (5.18)
    n = h.shape[1]
    idx = np.arange(n)
    td[:, idx, idx] = tdii
    return GTDT(tg, td, tg_inv)


def external_responses(model: GTDT, x: np.ndarray) -> np.ndarray:
    """``x^ext = (T^G)⁻¹ x`` (eq 5.19); ``x`` of shape ``(F, n)`` or ``(n,)``."""
    xx = _responses(model, x)
    return np.einsum("fij,fj->fi", model.inv_global, xx)


def _responses(model: GTDT, x: np.ndarray) -> np.ndarray:
    xx = np.asarray(x, dtype=complex)
    if xx.ndim == 1:
        xx = xx[None]
    if xx.shape != model.direct.shape[:2]:
        raise InputError(
            f"x: operational responses must have shape {model.direct.shape[:2]}, got {xx.shape}"
        )
    return xx


def path_contributions(model: GTDT, x: np.ndarray) -> np.ndarray:
    """Partial path contributions ``P[f, i, j]``: for j ≠ i, ``T^D_ij x_j``; on the diagonal the
    external part ``T^D_ii x^ext_i``. Summing over j reconstructs ``x_i`` (eq 5.21)."""
    xx = _responses(model, x)
    xe = external_responses(model, xx)
    p = model.direct * xx[:, None, :]
    n = xx.shape[1]
    idx = np.arange(n)
    p[:, idx, idx] = model.direct[:, idx, idx] * xe
    return p


def reconstruct(model: GTDT, x: np.ndarray) -> np.ndarray:
    """Reconstruction ``x = (T^D − Λ_TD) x + Λ_TD x^ext`` (eq 5.21), shape ``(F, n)``."""
    return path_contributions(model, x).sum(axis=2)
