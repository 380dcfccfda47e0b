"""Shaft torque from a full-bridge torsion strain gauge (seed 003 eqs 4.15-4.16).

Hammami (2015, ch. 4) measures the motor torque with a full Wheatstone bridge on the sun shaft:

    M_t = ½ ε G S_p        (4.15)
    S_p = π d³ / 16        (4.16, polar section modulus of a solid round shaft)

with ε the strain *indicated* by the bridge. A torsion bridge has four active gauges at ±45°
to the shaft axis; in pure shear each reads ±γ/2 (γ the engineering shear strain), so the bridge
indicates ε = 4·γ/2 = 2γ and (4.15) is Hooke's law τ = G γ = G ε/2 times S_p. SI units:
strain [m/m], G [Pa], d [m], torque [N·m].
"""

from __future__ import annotations

import numpy as np

from geardyn.errors import InputError


def polar_section_modulus(diameter_m: float) -> float:
    """S_p = π d³/16 (m³) of a solid round shaft (seed 003 eq 4.16)."""
    d = _positive("diameter_m", diameter_m, "shaft diameter (m)")
    return float(np.pi * d**3 / 16.0)


def torque_from_bridge_strain(
    strain: np.ndarray | float, shear_modulus_pa: float, diameter_m: float
) -> np.ndarray:
    """Shaft torque M_t = ½ ε G S_p (N·m) from the full-bridge indicated strain ε (m/m)
    (seed 003 eq 4.15); ``strain`` may be a time history."""
    g = _positive("shear_modulus_pa", shear_modulus_pa, "shear modulus (Pa)")
    eps = np.asarray(strain, dtype=float)
    if not np.all(np.isfinite(eps)):
        raise InputError("strain: the bridge strain contains NaN or infinite values")
    return 0.5 * eps * g * polar_section_modulus(diameter_m)


def bridge_strain_from_torque(
    torque_nm: np.ndarray | float, shear_modulus_pa: float, diameter_m: float
) -> np.ndarray:
    """Inverse of :func:`torque_from_bridge_strain`: ε = 2 M_t/(G S_p) (m/m), e.g. to synthesise
    the strain-gauge channel from a simulated shaft torque."""
    g = _positive("shear_modulus_pa", shear_modulus_pa, "shear modulus (Pa)")
    t = np.asarray(torque_nm, dtype=float)
    if not np.all(np.isfinite(t)):
        raise InputError("torque_nm: the torque contains NaN or infinite values")
    return 2.0 * t / (g * polar_section_modulus(diameter_m))


def _positive(name: str, value: float, what: str) -> float:
    v = float(value)
    if not np.isfinite(v) or v <= 0:
        raise InputError(f"{name}: the {what} must be a finite number > 0, got {value!r}")
    return v
