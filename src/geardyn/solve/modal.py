"""Modal analysis of lumped-parameter models (seed 003 ch. 3; Lin & Parker 1999).

- :func:`modes` solves ω² M φ = K φ (seed 003 eq 3.27), mass-normalised φ, frequencies in Hz
  (generic solver and energies: :mod:`geardyn.solve.eigen`, shared by every model).
- Degenerate frequencies are grouped (multiplicity) and each mode is classified from its
  shape as in Lin & Parker (1999): *rotational* (central members only rotate, all planets move
  alike), *translational* (central members only translate), *planet* (central members at
  rest), else *mixed*; ``rigid`` for 0 Hz. The test uses the whole degenerate subspace.
- Modal kinetic energy per DOF Ec_k = ½ ω² φ_k (Mφ)_k (seed 003 eq 3.29) and strain energy per
  spring Ep_e = ½ k_e (a_eᵀφ)² (eq 3.28); each set of bins sums to the mode's total energy.
- :func:`campbell` gives the frequencies of M q̈ + Ω G q̇ + (K − Ω² K_Ω) q = 0 (eq 3.1).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from geardyn.errors import InputError
from geardyn.models.planetary.model import PlanetaryModel
from geardyn.solve.eigen import campbell as eigen_campbell
from geardyn.solve.eigen import eigenmodes, kinetic_energy, participation, strain_rank_one

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


@dataclass
class ModalResult:
    """Frequencies (Hz), mass-normalised shapes (columns) and energy tables."""

    freq_hz: np.ndarray
    shapes: np.ndarray
    multiplicity: np.ndarray
    mode_type: list[str]
    kinetic: np.ndarray  # (n_modes, n_dof) J for unit modal amplitude
    strain: np.ndarray  # (n_modes, n_springs)
    dof_names: list[str]
    spring_names: list[str]
    spring_bins: list[str]
    mass_fraction: np.ndarray | None = None  # (n_modes, n_dof) φ_k (Mφ)_k, sums to 1

    def to_dataset(self) -> xr.Dataset:
        """xarray Dataset: freq (Hz), shape(mode, dof), energy fractions."""
        mode = np.arange(1, len(self.freq_hz) + 1)
        ek = self.kinetic / np.maximum(self.kinetic.sum(1, keepdims=True), 1e-300)
        ep = self.strain / np.maximum(self.strain.sum(1, keepdims=True), 1e-300)
        ds = xr.Dataset(
            {
                "frequency": ("mode", self.freq_hz, {"units": "Hz"}),
                "multiplicity": ("mode", self.multiplicity),
                "type": ("mode", np.array(self.mode_type)),
                "shape": (("mode", "dof"), self.shapes.T, {"units": "kg^-1/2 (mass-normalised)"}),
                "kinetic_fraction": (("mode", "dof"), ek, {"units": "1"}),
                "strain_fraction": (("mode", "spring"), ep, {"units": "1"}),
            },
            coords={"mode": mode, "dof": self.dof_names, "spring": self.spring_names},
        )
        return ds

    def table(self) -> list[dict]:
        """One row per mode: frequency, multiplicity, type, dominant motion and strain."""
        rows = []
        for i, f in enumerate(self.freq_hz):
            w = self.kinetic[i] if self.mass_fraction is None else self.mass_fraction[i]
            k = int(np.argmax(w))
            rigid = self.mode_type[i] == "rigid"
            s = -1 if rigid or self.strain[i].sum() <= 0 else int(np.argmax(self.strain[i]))
            rows.append(
                {
                    "mode": i + 1,
                    "freq_hz": float(f),
                    "multiplicity": int(self.multiplicity[i]),
                    "type": self.mode_type[i],
                    "dominant_motion": self.dof_names[k],
                    "dominant_strain": self.spring_names[s] if s >= 0 else "-",
                }
            )
        return rows

    def plot(self, ax: Axes | Sequence[Axes] | None = None, kind: str = "energy",
             max_hz: float | None = None, model: PlanetaryModel | None = None) -> Figure:
        """Figure of the modes (returned, never saved); modes up to ``max_hz`` [Hz].

        ``kind``: ``"energy"`` (default; two axes: ``"kinetic"`` energy per DOF, seed 003
        Table 3.4 layout, and ``"strain"`` energy per spring, in % of each mode's energy),
        ``"kinetic"``, ``"strain"`` (one axes each) or ``"frequencies"`` (natural frequency
        against mode number, one legend entry per mode type). With ``model`` the strain
        columns follow seed 003 Table 3.5 (:func:`strain_energy_table`). ``ax``: axes to draw
        on (two for ``"energy"``), else a new figure.
        """
        from geardyn.plotting import plot_mode_energies, plot_mode_frequencies

        kinds = ("energy", "kinetic", "strain", "frequencies")
        if kind not in kinds:
            raise InputError(f"kind: must be one of {', '.join(kinds)}, got {kind!r}")
        keep = np.ones(len(self.freq_hz), bool) if max_hz is None else self.freq_hz <= max_hz
        if not keep.any():
            raise InputError(f"max_hz: no mode at or below {max_hz:g} Hz (lowest "
                             f"{self.freq_hz[0]:.4g} Hz)")
        if kind == "frequencies":
            return plot_mode_frequencies(self.freq_hz[keep], np.array(self.mode_type)[keep], ax)
        tables = {}
        if kind in ("energy", "kinetic"):
            ek = self.kinetic / np.maximum(self.kinetic.sum(1, keepdims=True), 1e-300)
            tables["kinetic"] = (100 * ek[keep], self.dof_names, "degree of freedom [-]",
                                 "kinetic energy per DOF (Hammami 2015, Table 3.4 layout)")
        if kind in ("energy", "strain"):
            if model is not None:
                labels, ep = strain_energy_table(model, self)
            else:
                labels = self.spring_names
                ep = self.strain / np.maximum(self.strain.sum(1, keepdims=True), 1e-300)
            tables["strain"] = (100 * ep[keep], labels, "spring [-]",
                                "strain energy per spring"
                                + (" (Hammami 2015, Table 3.5 layout)" if model is not None
                                   else ""))
        return plot_mode_energies(self.freq_hz[keep], np.nonzero(keep)[0] + 1, tables, ax)


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
