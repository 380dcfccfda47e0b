"""Characteristic (defect) frequencies of a rolling-element bearing.

Classical kinematic formulas (no slip; e.g. Randall & Antoni, "Rolling element bearing
diagnostics — a tutorial", MSSP 25, 2011, eqs 1-4), written for the general case where both
rings turn about the same axis, as the contact frequencies of bearings on turning pairs in
seed 000 §4 (ref. [11]). With ``γ = (d/D)·cos α`` and ``f_r = f_inner − f_outer`` (signed,
Hz):

- cage relative to the outer ring:  ``FTF = f_r/2 · (1 − γ)``
- outer-race defect:                ``BPFO = n·|FTF|``
- inner-race defect:                ``BPFI = n·|f_r|/2 · (1 + γ)``
- element spin (w.r.t. the cage):   ``BSF = |f_r|·D/(2d) · (1 − γ²)``; an element defect
  strikes both races, at ``2·BSF``.

With a fixed outer ring ``FTF`` is the usual fundamental train frequency. Units: Hz in, Hz out;
diameters in metres (only their ratio matters); angle in radians.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np


@dataclass(frozen=True)
class BearingFrequencies:
    """Defect frequencies of one bearing (Hz); arrays when the speeds are arrays."""

    ftf: float | np.ndarray
    bpfo: float | np.ndarray
    bpfi: float | np.ndarray
    bsf: float | np.ndarray
    cage_abs: float | np.ndarray

    def as_dict(self) -> dict[str, float | np.ndarray]:
        return asdict(self)


def check_bearing_geometry(
    n_elements: int, element_diameter: float, pitch_diameter: float, contact_angle: float
) -> list[str]:
    """Rule violations of a bearing geometry, as messages naming the field (empty if valid)."""
    problems = []
    if int(n_elements) != n_elements or n_elements < 3:
        problems.append(f"n_elements: must be an integer ≥ 3 (got {n_elements})")
    if not element_diameter > 0:
        problems.append(f"element_diameter_m: must be > 0 (got {element_diameter})")
    if not pitch_diameter > 0:
        problems.append(f"pitch_diameter_m: must be > 0 (got {pitch_diameter})")
    elif element_diameter >= pitch_diameter:
        problems.append(
            f"element_diameter_m: {element_diameter} must be smaller than pitch_diameter_m "
            f"{pitch_diameter}"
        )
    elif n_elements >= 3 and element_diameter > pitch_diameter * math.sin(math.pi / n_elements):
        problems.append(
            f"n_elements: {n_elements} elements of diameter {element_diameter} m do not fit on "
            f"pitch diameter {pitch_diameter} m (need d ≤ D·sin(π/n))"
        )
    if not 0 <= contact_angle < math.pi / 2:
        problems.append(
            f"contact_angle_deg: must be in [0, 90) (got {math.degrees(contact_angle):.6g})"
        )
    return problems


def bearing_frequencies(
    f_inner: float | np.ndarray,
    f_outer: float | np.ndarray,
    n_elements: int,
    element_diameter: float,
    pitch_diameter: float,
    contact_angle: float = 0.0,
) -> BearingFrequencies:
    """Defect frequencies (Hz) from the signed rotation frequencies (Hz) of the two rings.

    ``f_inner`` and ``f_outer`` are the rotation frequencies of the inner and outer ring about
    the common bearing axis (same sign convention for both). ``cage_abs`` is the cage rotation
    frequency in the fixed frame, ``f_outer + FTF``.
    """
    problems = check_bearing_geometry(n_elements, element_diameter, pitch_diameter, contact_angle)
    if problems:
        raise ValueError("bearing geometry: " + "; ".join(problems))
    gamma = element_diameter / pitch_diameter * math.cos(contact_angle)
    fi = np.asarray(f_inner, dtype=float)
    fo = np.asarray(f_outer, dtype=float)
    fr = fi - fo
    ftf = 0.5 * fr * (1.0 - gamma)
    out = BearingFrequencies(
        ftf=np.abs(ftf),
        bpfo=n_elements * np.abs(ftf),
        bpfi=n_elements * 0.5 * np.abs(fr) * (1.0 + gamma),
        bsf=np.abs(fr) * pitch_diameter / (2.0 * element_diameter) * (1.0 - gamma**2),
        cage_abs=np.abs(fo + ftf),
    )
    if fi.ndim == 0 and fo.ndim == 0:
        out = BearingFrequencies(**{k: float(v) for k, v in out.as_dict().items()})
    return out
