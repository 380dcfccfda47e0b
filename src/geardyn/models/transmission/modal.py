"""Modes and Campbell diagram of the FE transmission (seed 002 eqs 2-3 linearised at the static
preload) in the :class:`geardyn.solve.modal.ModalResult` form of the lumped models.

* :func:`fe_modes` — frequencies, mass-normalised shapes on the named DOFs
  (``{shaft}.n{i}.{x,y,z,rx,ry,rz}``), multiplicities, a mode type from the kinetic energy
  (``torsional``: θz, ``lateral``: x, y, θx, θy, ``axial``: z; ``mixed`` when none holds half of
  it; ``rigid`` below :data:`RIGID_HZ`), modal kinetic energy per DOF ½ ω² φ_k (Mφ)_k and strain
  energy per element ½ φ_eᵀ K_e φ_e (seed 003 eqs 3.28-3.29 applied to element matrices): each
  Timoshenko element (``{shaft}.e{i}``), each bearing and each mesh (their tangent stiffness at
  the preload, finite differences of the connecting forces as in
  :func:`geardyn.models.transmission.simulate.connecting_jacobian`).
* :func:`fe_campbell` — whirl frequencies against the reference-shaft speed with the
  gyroscopic matrices of every shaft (:func:`geardyn.models.transmission.assembly.campbell`).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import xarray as xr

from geardyn.models.transmission.assembly import (
    NODE_DOFS,
    TransmissionModel,
    campbell,
)

#: Modes below this frequency [Hz] are the drive line's rigid-body rotation.
RIGID_HZ = 0.5
#: DOF label → motion group of the mode type.
MOTION = {"x": "lateral", "y": "lateral", "rx": "lateral", "ry": "lateral", "z": "axial",
          "rz": "torsional"}


def _one(soa, i: int):  # noqa: ANN001, ANN202
    """Element ``i`` of a structure-of-arrays (:class:`.Bearings`, :class:`.Meshes`)."""
    upd = {}
    for f in dataclasses.fields(soa):
        v = getattr(soa, f.name)
        if isinstance(v, np.ndarray) and v.ndim >= 1:
            upd[f.name] = v[i:i + 1].copy()
        elif isinstance(v, list) and v:
            upd[f.name] = v[i:i + 1]
    return dataclasses.replace(soa, **upd)


def element_tangents(model: TransmissionModel, q: np.ndarray, h: float = 1e-9
                     ) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(name, DOF indices, tangent stiffness −∂F/∂q on them, symmetrised) of every bearing
    (``bearing.{name}``, its node) and mesh (``mesh.{pair}``, its two nodes) at state ``q``."""
    from geardyn.models.transmission.kernels import bearing_forces, mesh_forces

    v = np.zeros(model.ndof)
    out = []

    def tangent(force, dofs: np.ndarray) -> np.ndarray:  # noqa: ANN001
        f0 = force(q)
        J = np.zeros((dofs.size, dofs.size))
        for jj, j in enumerate(dofs):
            qp = q.copy()
            qp[j] += h
            J[:, jj] = -(force(qp) - f0)[dofs] / h
        return 0.5 * (J + J.T)

    def force_of(kernel, args: tuple, out_shape: tuple[int, ...]):  # noqa: ANN001, ANN202
        def force(qq: np.ndarray) -> np.ndarray:
            f = np.zeros(model.ndof)
            kernel(qq, v, f, np.zeros(5), *args, np.zeros(out_shape))
            return f
        return force

    bs, mh = model.bearings, model.meshes
    node = np.arange(6)
    for i, name in enumerate(bs.names):
        dofs = 6 * int(bs.node[i]) + node
        fb = force_of(bearing_forces, _one(bs, i).args(), (1, 3))
        out.append((f"bearing.{name}", dofs, tangent(fb, dofs)))
    for i, name in enumerate(mh.names):
        dofs = np.concatenate([6 * int(mh.na[i]) + node, 6 * int(mh.nb[i]) + node])
        fm = force_of(mesh_forces, _one(mh, i).args(), (1,))
        out.append((f"mesh.{name}", dofs, tangent(fm, dofs)))
    for sp in model.supports:  # linear supports (x, y, θx, θy) and their axial stiffness
        dofs = np.concatenate([sp.dofs, [6 * sp.node + 2]])
        k = np.zeros((5, 5))
        k[:4, :4] = 0.5 * (sp.K + sp.K.T)
        k[4, 4] = sp.kzz
        out.append((f"support.{sp.name}", dofs, k))
    return out


def fe_modes(model: TransmissionModel, prepared=None):  # noqa: ANN001, ANN201
    """Modes of the FE transmission linearised at the static preload (gyroscopic terms
    neglected), as a :class:`geardyn.solve.modal.ModalResult`; ``prepared``: the
    :func:`~geardyn.models.transmission.simulate.prepare` result (computed if None). Generic
    part :func:`geardyn.solve.eigen.eigenmodes` (degenerate within 1e-6 relative or 1e-6 Hz;
    modes below :data:`RIGID_HZ` rigid, 0 Hz)."""
    from geardyn.models.transmission.simulate import prepare
    from geardyn.solve.eigen import eigenmodes, kinetic_energy, participation, strain_blocks
    from geardyn.solve.modal import ModalResult

    prep = prepared if prepared is not None else prepare(model)
    M = model.M
    em = eigenmodes(M, prep.K_lin, zero_hz=RIGID_HZ, rtol=1e-6, atol_hz=1e-6)
    f, phi = em.freq_hz, em.shapes
    frac = participation(M, phi)  # (mode, dof), rows sum to 1 (mass-normalised)
    names = model.dof_names
    labels = [n.rsplit(".", 1)[1] for n in names]
    groups = {g: np.array([MOTION[lab] == g for lab in labels]) for g in set(MOTION.values())}
    elements = []
    asm = model.assembly
    if asm is not None:
        for b in asm.blocks:
            if "K" in b.mats:
                elements.append((b.name, b.dofs, b.mats["K"]))
    elements += element_tangents(model, prep.q0)
    strain = strain_blocks(phi, [(dofs, k) for _, dofs, k in elements])
    types = []
    for i in range(f.size):
        if em.rigid[i]:
            types.append("rigid")
            continue
        share = {g: float(frac[i, sel].sum()) for g, sel in groups.items()}
        g = max(share, key=share.get)
        types.append(g if share[g] >= 0.5 else "mixed")
    bins = [e[0].split(".", 1)[0] if e[0].split(".", 1)[0] in ("bearing", "mesh", "support")
            else "shaft" for e in elements]
    return ModalResult(f, phi, em.multiplicity, types, kinetic_energy(M, f, phi), strain,
                       list(names), [e[0] for e in elements], bins, frac)


def fe_campbell(model: TransmissionModel, prepared, speeds_rpm: np.ndarray,  # noqa: ANN001
                n_modes: int = 20, reference: str | None = None, track: bool = False
                ) -> xr.DataArray:
    """Whirl frequencies (Hz) of M q̈ + G(Ω) q̇ + K_lin q = 0 against the speed of the
    ``reference`` shaft (rpm; default: the one of ``prepared``), every shaft spinning at its
    kinematic ratio (:func:`geardyn.models.transmission.assembly.campbell`); ``track``: each
    column follows one mode along the speeds instead of sorted frequencies."""
    from geardyn.models.transmission.simulate import speed_ratios

    ratios = prepared.speed_ratio if reference is None else None
    if ratios is None or not ratios:
        from geardyn.errors import InputError

        ref = reference or next(iter(model.shaft_nodes))
        if ref not in model.shaft_nodes:
            raise InputError(f"--speed-of / reference shaft: '{ref}' is not a shaft (one of "
                             f"{', '.join(model.shaft_nodes)})")
        ratios = speed_ratios(model, ref)
    ref = next(iter(ratios))  # speed_ratios puts the reference shaft first
    cd = campbell(model, prepared.K_lin, np.asarray(speeds_rpm, float), ratios, n_modes=n_modes,
                  track=track)
    cd.attrs.update({"speed_of": ref, "speed_units": "rpm"})
    return cd


def damped_modes(model: TransmissionModel, prepared, speed_rpm: float = 0.0,  # noqa: ANN001
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Complex modes of M q̈ + (C + Σ_s Ω_s G_s) q̇ + K_lin q = 0 at ``speed_rpm`` of the
    reference shaft (``prepared.speed_ratio``): C the run's damping (modal + supports and
    dashpots, ``prepared.C``), state-space eigenvalues λ of [[0, I], [−M⁻¹K, −M⁻¹C_Ω]]
    (Friswell et al. 2010, §3.7). Returns (ω_n = |λ| [rad/s], ω_d = Im λ [rad/s], ζ = −Re λ/|λ|)
    of the eigenvalues with Im λ > 0, sorted by ω_n; ``ω_n/2π`` is ROSS's ``wn``."""
    import math

    from scipy.linalg import eig, solve

    M, K = model.M, prepared.K_lin
    C = np.array(prepared.C, float)
    w = speed_rpm * math.pi / 30.0
    for s, g in model.gyroscopic.items():
        C = C + model.shaft_sign[s] * prepared.speed_ratio.get(s, 0.0) * w * g
    n = M.shape[0]
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -solve(M, K)
    A[n:, n:] = -solve(M, C)
    lam = eig(A, right=False)
    # oscillating modes only: Im λ > 0, above the rigid-body rotation (< RIGID_HZ)
    lam = lam[(lam.imag > 0) & (np.abs(lam) >= 2 * math.pi * RIGID_HZ)]
    wn = np.abs(lam)
    o = np.argsort(wn)
    return wn[o], lam.imag[o], -lam.real[o] / wn[o]


def unbalance_response(model: TransmissionModel, prepared, speed_rpm: float,  # noqa: ANN001
                       node: int, mass_eccentricity: float, phase_deg: float = 0.0
                       ) -> np.ndarray:
    """Steady 1× response (complex amplitudes of every DOF, m and rad, e^{iΩt} convention) to
    an unbalance m e at global ``node`` at constant ``speed_rpm`` of the reference shaft:
    (K_lin − Ω² M + iΩ (C + Σ_s Ω_s G_s)) X = F, F_x = m e Ω² e^{iφ}, F_y = −i F_x (the force
    m e Ω² (cos(Ωt + φ), sin(Ωt + φ)) of :func:`geardyn.solve.explicit.applied_loads`;
    Friswell et al. 2010, §3.8)."""
    import math

    M, K = model.M, prepared.K_lin
    w = speed_rpm * math.pi / 30.0
    C = np.array(prepared.C, float)
    for s, g in model.gyroscopic.items():
        C = C + model.shaft_sign[s] * prepared.speed_ratio.get(s, 0.0) * w * g
    n = M.shape[0]
    F = np.zeros(n, complex)
    F[6 * node] = mass_eccentricity * w * w * np.exp(1j * math.radians(phase_deg))
    F[6 * node + 1] = -1j * F[6 * node]
    if w == 0.0:
        return np.zeros(n, complex)
    # rigid-body modes (free rotation, free axial motion) keep −Ω² M: A is regular for Ω > 0
    return np.linalg.solve(K - w * w * M + 1j * w * C, F)


__all__ = ["MOTION", "NODE_DOFS", "RIGID_HZ", "damped_modes", "element_tangents",
           "fe_campbell", "fe_modes", "unbalance_response"]
