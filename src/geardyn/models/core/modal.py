"""Modes of the general torsional model: ω² M φ = K φ with the mean mesh stiffnesses.

Same result object as the planetary model (:class:`geardyn.solve.modal.ModalResult`):
frequencies (Hz), mass-normalised shapes, multiplicities, kinetic energy per DOF
Ec_k = ½ ω² φ_k (Mφ)_k and strain energy per element Ep_e = ½ k_e (a_eᵀφ)² (seed 003 eqs
3.28-3.29). Mode types: ``rigid`` below ``zero_hz`` (the kinematic nullspace, seed 000
eq 5), else by the share of the mass-weighted shape in lateral DOFs (x, y, ζ, η):
``torsional`` (< 0.1 %), ``lateral`` (> 99.9 %) or ``coupled``.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import xarray as xr

from geardyn.models.core.model import CoreModel
from geardyn.solve.modal import ModalResult


def core_modes(model: CoreModel, rtol: float = 1e-6, atol_hz: float = 1e-3,
               zero_hz: float = 1e-2) -> ModalResult:
    """Natural frequencies, shapes and energies of ``model`` (mean mesh stiffness)."""
    mm = model.mass_matrix()
    kk = model.stiffness_matrix()
    w2, phi = sla.eigh(kk, mm)
    freq = np.sqrt(np.clip(w2, 0.0, None)) / (2 * np.pi)
    freq[freq < zero_hz] = 0.0
    mult = np.ones(len(freq), int)
    start = 0
    for i in range(1, len(freq) + 1):
        if i == len(freq) or abs(freq[i] - freq[start]) > max(atol_hz, rtol * freq[i]):
            mult[start:i] = i - start
            start = i
    w2v = (2 * np.pi * freq) ** 2
    kinetic = 0.5 * w2v[:, None] * (phi * (mm @ phi)).T
    share = (phi * (mm @ phi)).T  # mass-weighted participation per DOF, rows sum to 1
    lateral = np.array([nm.endswith((".x", ".y", ".zeta", ".eta")) for nm in model.dof_names])
    types = []
    for i, f in enumerate(freq):
        lat = float(share[i, lateral].sum()) if lateral.any() else 0.0
        types.append("rigid" if f == 0.0 else "torsional" if lat < 1e-3
                     else "lateral" if lat > 1 - 1e-3 else "coupled")
    rows = [m.a for m in model.meshes] + [s.a for s in model.springs]
    k = np.array([m.k_mean for m in model.meshes] + [s.k for s in model.springs])
    a = np.array(rows).reshape(len(rows), model.n)
    strain = 0.5 * k[None, :] * (a @ phi).T ** 2
    names = [m.name for m in model.meshes] + [s.name for s in model.springs]
    bins = [f"mesh {m.name}" for m in model.meshes] + [f"{s.kind} {s.name}"
                                                          for s in model.springs]
    return ModalResult(freq, phi, mult, types, kinetic, strain, list(model.dof_names), names,
                       bins, (phi * (mm @ phi)).T)


def core_campbell(model: CoreModel, body: str, speeds_rad_s: np.ndarray,
                  n_modes: int | None = None) -> xr.DataArray:
    """Natural frequencies (Hz) against the speed of ``body`` with the gyroscopic and
    centripetal terms of every carrier frame (lateral model; seed 003 eq 3.1, homogeneous part):
    M q̈ + Σ_c Ω_c G_c q̇ + (K − Σ_c Ω_c² K_Ω,c) q = 0 with Ω_c = r_c·q̇_rigid, the rigid-body
    motion (kinematic, 1 DOF) in which ``body`` turns at the given speed. State-space form;
    the ``n_modes`` lowest non-negative frequencies per speed (as :func:`geardyn.solve.modal.
    campbell`)."""
    from geardyn.errors import InputError

    mm, kk = model.mass_matrix(), model.stiffness_matrix()
    null = sla.null_space(kk, rcond=1e-10)
    if null.shape[1] != 1:
        raise InputError(f"campbell: needs a mechanism with one rigid-body motion (this model "
                         f"has {null.shape[1]})")
    h = model.body(body).rotation @ null[:, 0]
    if abs(h) < 1e-12:
        raise InputError(f"campbell: '{body}' does not turn in the rigid-body motion")
    rigid = null[:, 0] / h  # body at 1 rad/s
    n = model.n
    n_modes = n_modes or n
    minv = np.linalg.inv(mm)
    speeds = np.asarray(speeds_rad_s, float)
    out = np.full((len(speeds), n_modes), np.nan)
    for i, w in enumerate(speeds):
        g = np.zeros((n, n))
        ko = np.zeros((n, n))
        for rate, gg, kk_om in model.rotating:
            om = float(rate @ rigid) * w
            g += om * gg
            ko += om * om * kk_om
        a = np.zeros((2 * n, 2 * n))
        a[:n, n:] = np.eye(n)
        a[n:, :n] = -minv @ (kk - ko)
        a[n:, n:] = -minv @ g
        f = np.sort(np.abs(np.linalg.eigvals(a).imag))[::2] / (2 * np.pi)
        out[i, : min(n_modes, len(f))] = f[:n_modes]
    return xr.DataArray(out, dims=("speed", "mode"),
                        coords={"speed": speeds, "mode": np.arange(1, n_modes + 1)},
                        name="frequency", attrs={"units": "Hz", "speed_units": "rad/s",
                                                 "speed_of": body})
