"""Simple mesh-stiffness models for quick studies and cross-checks.

* Square wave from k_max, k_min and the contact ratio (seed 003 eqs 1.11-1.13): k = k_max
  during double contact (the first (c − 1) of each mesh period T_m), k_min otherwise.
* ISO 6336-1:2019 method B single-pair stiffness c' and mesh stiffness c_γα (§9; eqs 45-50,
  coefficients of Table 9), with the Henriot/Weber form of seed 003 eq 1.14 as a special case.

Units: stiffness per unit face width in N/(m·m) (SI) — the ISO unit N/(mm·µm) equals
1e9 N/m² — and mesh stiffness in N/m.
"""

from __future__ import annotations

import math

import numpy as np

from geardyn.errors import InputError

#: ISO 6336-1 Table 9 coefficients C1..C9 for q' (mm·µm/N).
ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)


def square_wave(t: np.ndarray, k_max: float, k_min: float, contact_ratio: float) -> np.ndarray:
    """Square-wave stiffness at times ``t`` given in mesh periods (seed 003 eq 1.11, exact form).

    k = k_max for t mod 1 ∈ [0, c − 1) (double contact), k_min otherwise; 1 < c ≤ 2.
    """
    if not 1.0 <= contact_ratio <= 2.0:
        raise InputError(f"contact ratio {contact_ratio} must be in [1, 2] for the square wave")
    if k_min > k_max:
        raise InputError(f"k_min {k_min} must not exceed k_max {k_max}")
    ph = np.mod(np.asarray(t, dtype=float), 1.0)
    return np.where(ph < contact_ratio - 1.0, k_max, k_min)


def square_wave_mean(k_max: float, k_min: float, contact_ratio: float) -> float:
    """Mean stiffness k̄ = k_max(c − 1) + (2 − c)k_min (seed 003 eq 1.12)."""
    return k_max * (contact_ratio - 1.0) + (2.0 - contact_ratio) * k_min


def square_wave_fourier(
    t: np.ndarray, k_max: float, k_min: float, contact_ratio: float, n_harmonics: int = 50
) -> np.ndarray:
    """Truncated Fourier series of the square wave (seed 003 eq 1.11 with eqs 1.12-1.13).

    k(t) = k̄ + (Δk/π) Σ_i (1/i)[sin(2iπ(c−1)) cos(2iπt) + (1 − cos(2iπ(c−1))) sin(2iπt)],
    t in mesh periods, Δk = k_max − k_min.
    """
    t = np.asarray(t, dtype=float)
    c1 = contact_ratio - 1.0
    dk = k_max - k_min
    out = np.full(t.shape, square_wave_mean(k_max, k_min, contact_ratio))
    for i in range(1, n_harmonics + 1):
        out += (
            dk
            / (math.pi * i)
            * (
                math.sin(2 * i * math.pi * c1) * np.cos(2 * i * math.pi * t)
                + (1 - math.cos(2 * i * math.pi * c1)) * np.sin(2 * i * math.pi * t)
            )
        )
    return out


def iso_q_prime(zn1: float, zn2: float, x1: float = 0.0, x2: float = 0.0) -> float:
    """ISO 6336-1 minimum flexibility q' (mm·µm/N) of a solid spur pair (eq 47 / Table 9).

    ``zn2 = math.inf`` for an internal gear (ISO: use z_n2 = ∞).
    """
    c = ISO_C
    inv2 = 0.0 if math.isinf(zn2) else 1.0 / zn2
    return (
        c[0]
        + c[1] / zn1
        + c[2] * inv2
        + c[3] * x1 / zn1
        + c[4] * x1
        + c[5] * x2 * inv2
        + c[6] * x2
        + c[7] * x1**2
        + c[8] * x2**2
    )


def iso_single_pair_stiffness(
    z1: int,
    z2: int,
    x1: float = 0.0,
    x2: float = 0.0,
    helix_angle: float = 0.0,
    normal_pressure_angle: float = math.radians(20.0),
    dedendum_coef_rack: float = 1.25,
    internal: bool = False,
    load_per_width: float | None = None,
    c_m: float = 0.8,
    c_r: float = 1.0,
    e_ratio: float = 1.0,
) -> float:
    """ISO 6336-1 single-pair stiffness c' (N/(m·m), i.e. per metre of face width).

    c' = c'_th C_M C_R C_B cos β (eq 45) with c'_th = 1/q', virtual tooth numbers
    z_n = z/cos³β, C_B = [1 + 0.5(1.2 − h_fP/m_n)][1 − 0.02(20° − α_n)], C_M = 0.8, C_R = 1
    (solid blanks). ``load_per_width`` F_t·K_A/b (N/m) below 100 N/mm multiplies by
    (F_t K_A/b / 100 N/mm)^0.25. ``e_ratio`` = E/E_steel for other materials.
    """
    cb3 = math.cos(helix_angle) ** 3
    zn1 = z1 / cb3
    zn2 = math.inf if internal else z2 / cb3
    q = iso_q_prime(zn1, zn2, x1, x2)
    c_th = 1.0 / q
    c_b = (1.0 + 0.5 * (1.2 - dedendum_coef_rack)) * (
        1.0 - 0.02 * (20.0 - math.degrees(normal_pressure_angle))
    )
    c = c_th * c_m * c_r * c_b * math.cos(helix_angle) * e_ratio
    if load_per_width is not None:
        w = load_per_width / 1e3  # N/mm
        if w < 100.0:
            c *= (w / 100.0) ** 0.25
    return c * 1e9


def iso_mesh_stiffness(c_prime: float, contact_ratio: float) -> float:
    """ISO 6336-1 mesh stiffness per unit width c_γα = c'(0.75 ε_α + 0.25) (eq 50), same unit."""
    return c_prime * (0.75 * contact_ratio + 0.25)


def henriot_mean_stiffness(face_width: float, z1: int, z2: int) -> float:
    """Seed 003 eq 1.14 (Henriot): k̄ = b/(A₁ + A₂/z₁ + A₃/z₂) with b in m, result in N/m.

    A₁..A₃ = 0.04723, 0.15551, 0.25791 (the ISO C₁..C₃; the formula gives N/(µm·mm) × b[mm]).
    """
    return face_width * 1e3 / (0.04723 + 0.15551 / z1 + 0.25791 / z2) * 1e6
