"""The modal result of every lumped model (:class:`ModalResult`: frequencies, shapes, mode
types, energy tables, ``to_dataset``, ``table``, ``plot``). The planetary model's analysis
(:func:`geardyn.models.planetary.modal.modes`, ``campbell``, ``strain_energy_table``) lives
with that model; the solver knows no model (its generic part: :mod:`geardyn.solve.eigen`).

The planetary analysis (Hammami 2015, ch. 3; Lin & Parker 1999):

- ``modes`` solves ω² M φ = K φ (seed 003 eq 3.27), mass-normalised φ, frequencies in Hz
  (generic solver and energies: :mod:`geardyn.solve.eigen`, shared by every model).
- Degenerate frequencies are grouped (multiplicity) and each mode is classified from its
  shape as in Lin & Parker (1999): *rotational* (central members only rotate, all planets move
  alike), *translational* (central members only translate), *planet* (central members at
  rest), else *mixed*; ``rigid`` for 0 Hz. The test uses the whole degenerate subspace.
- Modal kinetic energy per DOF Ec_k = ½ ω² φ_k (Mφ)_k (seed 003 eq 3.29) and strain energy per
  spring Ep_e = ½ k_e (a_eᵀφ)² (eq 3.28); each set of bins sums to the mode's total energy.
- ``campbell`` gives the frequencies of M q̈ + Ω G q̇ + (K − Ω² K_Ω) q = 0 (eq 3.1).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from geardyn.errors import InputError

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from geardyn.models.planetary.model import PlanetaryModel


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
        columns follow seed 003 Table 3.5 (the model's ``strain_energy_table``). ``ax``: axes
        to draw on (two for ``"energy"``), else a new figure.
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
                labels, ep = model.strain_energy_table(self)
            else:
                labels = self.spring_names
                ep = self.strain / np.maximum(self.strain.sum(1, keepdims=True), 1e-300)
            tables["strain"] = (100 * ep[keep], labels, "spring [-]",
                                "strain energy per spring"
                                + (" (Hammami 2015, Table 3.5 layout)" if model is not None
                                   else ""))
        return plot_mode_energies(self.freq_hz[keep], np.nonzero(keep)[0] + 1, tables, ax)


#: Names that moved to :mod:`geardyn.models.planetary.modal` (the solver knows no model);
#: reached here only by old imports, resolved on first use.
_MOVED = ("modes", "campbell", "strain_energy_table")


def __getattr__(name: str):  # noqa: ANN202 - module attribute hook (PEP 562)
    if name in _MOVED:
        from geardyn.models.planetary import modal

        return getattr(modal, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
