"""The integrator's :class:`~geardyn.solve.integrate.LinearSystem` from an :class:`Assembly`.

One builder for every lumped model (the Lin & Parker planetary stages and the graph → model of
any mechanism): from the assembly's matrices (SI units) and the rank-one elements that vary in
time (the meshes, handed over as variable-spring rows),

* M — the assembled mass matrix;
* K₀ — the rank-one elements that do not vary, Σ k a aᵀ, plus the stiffness blocks;
* C₀ — Rayleigh damping α M + β K_mean on the mean stiffness (all rank-one elements at their
  registered k, the meshes at their mean; seed 003 eq 1.16), modal damping ratio ζ on every
  elastic mode of (K_mean, M): C += M Φ diag(2ζω_i) Φᵀ M with mass-normalised Φ (seed 003
  eq 1.16, c_i = 2 m_i ω_i ζ_i; rigid-body modes stay undamped), the viscous dampers c a aᵀ
  of the constant rank-one elements, the damping blocks, and dampers on named DOFs;
* the gyroscopic frames: Ω G q̇ − Ω² K_Ω q per rotating frame of the assembly at its rate
  Ω = r·q̇ (seed 003 eq 3.1).

``transform`` T (full = T · solved) reduces every matrix (Tᵀ X T) and row (a T), as the
planetary model's torsional and transverse reductions (seed 003 model B).
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence

import numpy as np

from geardyn.errors import ConfigError
from geardyn.models.core.assembly import Assembly
from geardyn.solve.integrate import Drives, LinearSystem, MassSchedule, VarSprings

#: Modes below this frequency (Hz) count as rigid-body modes (no modal damping).
RIGID_HZ = 1e-2


def _reduce(x: np.ndarray, t: np.ndarray | None) -> np.ndarray:
    return x if t is None else t.T @ x @ t


def modal_damping_matrix(k_mean: np.ndarray, mass: np.ndarray, zeta: float) -> np.ndarray:
    """M Φ diag(2ζω_i) Φᵀ M over the elastic modes of (K_mean, M) (seed 003 eq 1.16)."""
    import scipy.linalg as sla

    w2, phi = sla.eigh(k_mean, mass)
    w = np.sqrt(np.clip(w2, 0.0, None))
    w[w < 2 * np.pi * RIGID_HZ] = 0.0  # rigid-body modes stay undamped
    mp = mass @ phi
    return mp @ np.diag(2 * zeta * w) @ mp.T


def linear_system(
    asm: Assembly,
    variable: Sequence[dict] = (),
    varying: Collection[int] = (),
    *,
    transform: np.ndarray | None = None,
    names: Sequence[str] | None = None,
    rayleigh: tuple[float, float] = (0.0, 0.0),
    modal_damping: float = 0.0,
    support_damping: Mapping[str, float] | None = None,
    drives: list[dict] | None = None,
    force_t: np.ndarray | None = None,
    force: np.ndarray | None = None,
    mass_schedule: MassSchedule | None = None,
    gyroscopic: bool = False,
) -> LinearSystem:
    """The integrator system of ``asm`` (module docstring).

    ``variable``: the variable-spring rows (dicts of :meth:`VarSprings.build`, in solved
    coordinates) that replace the rank-one elements of indices ``varying`` in K₀ and C₀;
    ``names``: solved DOF names (default the assembly's), used by ``support_damping``
    (DOF name → N·s/m, or N·m·s/rad on rotations).
    """
    t = transform
    names = list(asm.names if names is None else names)
    n = len(names)
    rows = asm.rows()
    if t is not None:
        rows = rows @ t
    skip = set(varying)
    kk = np.zeros((n, n))
    for i, e in enumerate(asm.rank_one):
        if i not in skip:
            kk += e.k * np.outer(rows[i], rows[i])
    if any("K" in b.mats for b in asm.blocks):
        kk += _reduce(asm.block_matrix("K"), t)  # type: ignore[arg-type]
    mm = _reduce(asm.matrix("M"), t)  # type: ignore[arg-type]
    k_mean = _reduce(asm.matrix("K"), t)  # type: ignore[arg-type]
    cc = rayleigh[0] * mm + rayleigh[1] * k_mean
    if modal_damping > 0:
        cc += modal_damping_matrix(k_mean, mm, modal_damping)
    for i, e in enumerate(asm.rank_one):
        if e.c != 0.0 and i not in skip:
            cc += e.c * np.outer(rows[i], rows[i])
    if any("C" in b.mats for b in asm.blocks):
        cc += _reduce(asm.block_matrix("C"), t)  # type: ignore[arg-type]
    for name, c in (support_damping or {}).items():
        if name not in names:
            raise ConfigError(f"support_damping: unknown DOF '{name}' (available: "
                              f"{', '.join(names)})")
        j = names.index(name)
        cc[j, j] += c
    frames = asm.frame_terms() if gyroscopic else []
    return LinearSystem(
        mm, cc, kk, VarSprings.build(list(variable), n), Drives.build(drives or []),
        np.zeros(0) if force_t is None else np.asarray(force_t, float),
        np.zeros((0, n)) if force is None else np.asarray(force, float),
        mass_schedule or MassSchedule(), names,
        gyro_g=np.array([_reduce(g, t) for _f, _r, g, _k in frames]).reshape(len(frames), n, n),
        gyro_k=np.array([_reduce(k, t) for _f, _r, _g, k in frames]).reshape(len(frames), n, n),
        gyro_rate=np.array([r if t is None else r @ t for _f, r, _g, _k in frames]
                           ).reshape(len(frames), n),
    )
