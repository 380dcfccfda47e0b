"""Modal analysis of the planetary lumped model (Hammami 2015, ch. 3; Lin & Parker 1999).

- :func:`modes` solves ω² M φ = K φ (Hammami 2015, eq 3.27), mass-normalised φ, frequencies
  in Hz (generic solver and energies: :mod:`geardyn.solve.eigen`; result:
  :class:`geardyn.solve.modal.ModalResult`, shared by every model).
- Degenerate frequencies are grouped (multiplicity) and each mode is classified from its
  shape as in Lin & Parker (1999): *rotational* (central members only rotate, all planets move
  alike), *translational* (central members only translate), *planet* (central members at
  rest), else *mixed*; ``rigid`` for 0 Hz. The test uses the whole degenerate subspace.
- Modal kinetic energy per DOF Ec_k = ½ ω² φ_k (Mφ)_k (eq 3.29) and strain energy per
  spring Ep_e = ½ k_e (a_eᵀφ)² (eq 3.28); each set of bins sums to the mode's total energy.
- :func:`campbell` gives the frequencies of M q̈ + Ω G q̇ + (K − Ω² K_Ω) q = 0 (eq 3.1).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from geardyn.solve.eigen import campbell as eigen_campbell
from geardyn.solve.eigen import eigenmodes, kinetic_energy, participation, strain_rank_one
from geardyn.solve.modal import ModalResult

if TYPE_CHECKING:
    from geardyn.models.planetary.model import PlanetaryModel


def _classify(model: PlanetaryModel, phi: np.ndarray, tol: float = 1e-3) -> str:
    """Lin & Parker mode type of a subspace ``phi`` (full coordinates, columns)."""
    m = model.mass_diag
    trans, rot, plan = 0.0, 0.0, 0.0
    for b in model.bodies.values():
        e = (m[b.dofs, None] * phi[b.dofs] ** 2).sum()
        if b.kind == "central":
            trans += (m[b.dofs[:2], None] * phi[b.dofs[:2]] ** 2).sum()
            rot += (m[b.dofs[2], None] * phi[b.dofs[2]] ** 2).sum()
        elif b.kind == "planet":
            plan += e
        else:
            rot += e
    tot = trans + rot + plan
    if tot <= 0:
        return "mixed"
    # planets of each stage moving alike (same ζ, η, u): the rotational-mode signature
    alike = True
    scale = np.sqrt(np.max(m[:, None] * phi**2))
    for info in model.stages.values():
        ps = [model.bodies[info.bodies[f"planet{i + 1}"]] for i in range(len(info.psi))]
        for p in ps[1:]:
            if np.max(np.abs(phi[p.dofs] - phi[ps[0].dofs])) * np.sqrt(ps[0].mass) > tol * scale:
                alike = False
    if trans / tot < tol and alike:
        return "rotational"
    if rot / tot < tol and trans / tot > tol:
        return "translational"
    if (trans + rot) / tot < tol:
        return "planet"
    return "mixed"


def modes(
    model: PlanetaryModel,
    rtol: float = 1e-6,
    atol_hz: float = 1e-3,
    zero_hz: float = 1e-2,
) -> ModalResult:
    """Natural frequencies, shapes, multiplicities, types and energies (seed 003 eqs 3.27-3.29).

    ``rtol``/``atol_hz`` decide when frequencies are degenerate; modes below ``zero_hz`` are
    rigid-body modes (0 Hz). Generic part: :func:`geardyn.solve.eigen.eigenmodes`.
    """
    mm = model.mass_matrix()
    em = eigenmodes(mm, model.stiffness_matrix(), zero_hz=zero_hz, rtol=rtol, atol_hz=atol_hz)
    freq, phi = em.freq_hz, em.shapes
    t = model.transform
    types = [""] * len(freq)
    for g in em.groups:
        kind = "rigid" if em.rigid[g[0]] else _classify(model, t @ phi[:, g])
        for i in g:
            types[i] = kind
    kvec = np.array([s.k for s in model.springs])
    return ModalResult(
        freq,
        phi,
        em.multiplicity,
        types,
        kinetic_energy(mm, freq, phi),
        strain_rank_one(phi, model.spring_vectors(), kvec),
        model.names,
        [s.name for s in model.springs],
        [s.bin for s in model.springs],
        participation(mm, phi),
    )


def campbell(model: PlanetaryModel, carrier_speeds_rad_s: np.ndarray, n_modes: int | None = None,
             track: bool = False) -> xr.DataArray:
    """Natural frequencies (Hz) vs carrier speed Ω with gyroscopic and centripetal terms.

    Quadratic eigenproblem of seed 003 eq 3.1 (homogeneous part) solved in state-space form
    (:func:`geardyn.solve.eigen.campbell`, every stage's frame at the carrier speed); returns
    the ``n_modes`` lowest non-negative frequencies per speed, sorted, or followed mode by mode
    along the speeds with ``track``.
    """
    mm = model.mass_matrix()
    n_modes = n_modes or mm.shape[0]
    out = eigen_campbell(mm, model.stiffness_matrix(),
                         [(1.0, model.gyroscopic_matrix(), model.centripetal_matrix())],
                         carrier_speeds_rad_s, n_modes, track=track)
    return xr.DataArray(
        out,
        dims=("carrier_speed", "mode"),
        coords={"carrier_speed": carrier_speeds_rad_s, "mode": np.arange(1, n_modes + 1)},
        name="frequency",
        attrs={"units": "Hz", "carrier_speed_units": "rad/s"},
    )


def strain_energy_table(model: PlanetaryModel, res: ModalResult) -> tuple[list[str], np.ndarray]:
    """Strain energy per mode in the seed 003 Table 3.5 layout (fractions of the total).

    Per stage: bearings of carrier, ring, sun (x, y, rotation) and of each planet (radial,
    tangential, rotation — the last is always 0, planets have no rotational support); then per
    stage the ring–planet and sun–planet meshes. Springs outside that layout (inter-stage
    shafts, rotor supports) are appended as extra bins so that every row sums to 1.
    """
    idx = {s.name: i for i, s in enumerate(model.springs)}
    labels: list[str] = []
    cols: list[np.ndarray] = []
    zero = np.zeros(res.strain.shape[0])
    used: set[int] = set()

    def take(name: str, label: str) -> None:
        labels.append(label)
        if name in idx:
            cols.append(res.strain[:, idx[name]])
            used.add(idx[name])
        else:
            cols.append(zero)

    for info in model.stages.values():
        for role in ("carrier", "ring", "sun"):
            b = info.bodies[role]
            for d in ("x", "y", "u"):
                take(f"{b}.bearing.{d}", f"bearing of {b} ({d})")
        for i in range(len(info.psi)):
            b = info.bodies[f"planet{i + 1}"]
            for d in ("zeta", "eta", "u"):
                take(f"{b}.bearing.{d}", f"bearing of {b} ({d})")
    for info in model.stages.values():
        for mesh in ("ring", "sun"):
            for i in range(len(info.psi)):
                b = info.bodies[f"planet{i + 1}"]
                take(f"{b}.mesh_{mesh}", f"mesh {info.bodies[mesh]}-{b}")
    for i, s in enumerate(model.springs):
        if i not in used:
            labels.append(s.bin or s.name)
            cols.append(res.strain[:, i])
    e = np.array(cols).T
    e[[t == "rigid" for t in res.mode_type]] = 0.0  # round-off only
    tot = e.sum(1, keepdims=True)
    return labels, np.divide(e, tot, out=np.zeros_like(e), where=tot > 0)
