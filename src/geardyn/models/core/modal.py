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
from geardyn.solve.eigen import campbell as eigen_campbell
from geardyn.solve.eigen import (
    eigenmodes,
    frame_terms,
    kinetic_energy,
    participation,
    strain_rank_one,
)
from geardyn.solve.modal import ModalResult


def core_modes(model: CoreModel, rtol: float = 1e-6, atol_hz: float = 1e-3,
               zero_hz: float = 1e-2) -> ModalResult:
    """Natural frequencies, shapes and energies of ``model`` (mean mesh stiffness); generic
    part :func:`geardyn.solve.eigen.eigenmodes`."""
    mm = model.mass_matrix()
    em = eigenmodes(mm, model.stiffness_matrix(), zero_hz=zero_hz, rtol=rtol, atol_hz=atol_hz)
    freq, phi = em.freq_hz, em.shapes
    share = participation(mm, phi)  # mass-weighted participation per DOF, rows sum to 1
    lateral = np.array([nm.endswith((".x", ".y", ".zeta", ".eta")) for nm in model.dof_names])
    types = []
    for i in range(freq.size):
        lat = float(share[i, lateral].sum()) if lateral.any() else 0.0
        types.append("rigid" if em.rigid[i] else "torsional" if lat < 1e-3
                     else "lateral" if lat > 1 - 1e-3 else "coupled")
    rows = [m.a for m in model.meshes] + [s.a for s in model.springs]
    k = np.array([m.k_mean for m in model.meshes] + [s.k for s in model.springs])
    strain = strain_rank_one(phi, np.array(rows), k)
    names = [m.name for m in model.meshes] + [s.name for s in model.springs]
    bins = [f"mesh {m.name}" for m in model.meshes] + [f"{s.kind} {s.name}"
                                                          for s in model.springs]
    return ModalResult(freq, phi, em.multiplicity, types, kinetic_energy(mm, freq, phi), strain,
                       list(model.dof_names), names, bins, share)


def core_campbell(model: CoreModel, body: str, speeds_rad_s: np.ndarray,
                  n_modes: int | None = None, track: bool = False) -> xr.DataArray:
    """Natural frequencies (Hz) against the speed of ``body`` with the gyroscopic and
    centripetal terms of every carrier frame (lateral model; seed 003 eq 3.1, homogeneous part):
    M q̈ + Σ_c Ω_c G_c q̇ + (K − Σ_c Ω_c² K_Ω,c) q = 0 with Ω_c = r_c·q̇_rigid, the rigid-body
    motion (kinematic, 1 DOF) in which ``body`` turns at the given speed. State-space form
    (:func:`geardyn.solve.eigen.campbell`); the ``n_modes`` lowest non-negative frequencies per
    speed, sorted, or followed mode by mode along the speeds with ``track``."""
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
    n_modes = n_modes or model.n
    speeds = np.asarray(speeds_rad_s, float)
    out = eigen_campbell(mm, kk, frame_terms(model.assembly, rigid), speeds, n_modes,
                         track=track)
    return xr.DataArray(out, dims=("speed", "mode"),
                        coords={"speed": speeds, "mode": np.arange(1, n_modes + 1)},
                        name="frequency", attrs={"units": "Hz", "speed_units": "rad/s",
                                                 "speed_of": body})
