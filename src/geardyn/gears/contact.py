"""Tooth contact compliance: constant Hertz form and the nonlinear Johnson law (seed 002 eqs 8-9).

Units: forces in N, lengths in m, moduli in Pa.
"""

from __future__ import annotations

import math

import numpy as np

from geardyn.errors import InputError


def hertz_compliance(e1: float, nu1: float, e2: float, nu2: float, width: float = 1.0) -> float:
    """Constant (load-independent) Hertzian contact compliance 1/k_h (m/N).

    1/k_h = 2/(π L)·[(1 − ν₁²)/E₁ + (1 − ν₂²)/E₂], i.e. k_h = π E L / (4(1 − ν²)) for equal
    materials (the usual PE-method form, Yang & Sun 1985, as used with Chen & Shao's model).
    """
    return 2.0 / (math.pi * width) * ((1 - nu1**2) / e1 + (1 - nu2**2) / e2)


def johnson_modulus(youngs_modulus: float, poisson_ratio: float) -> float:
    """E* = E / (2(1 − ν²)) as written in seed 002 eq 8 (identical materials)."""
    return youngs_modulus / (2.0 * (1.0 - poisson_ratio**2))


def johnson_deflection(
    force: np.ndarray | float, width: float, e_star: float, radius_sum: float
) -> np.ndarray:
    """Contact approach δ_c (m) of seed 002 eq 8 (Johnson, cylinder–cylinder).

    δ_c = F/(π L E*)·(ln(4π L E* ΔR / F) − 1); ΔR is the sum of the contacting radii of
    curvature (m), L the contact width (m). δ_c(0) = 0. Valid while F < 4π L E* ΔR / e²
    (where dδ/dF > 0), i.e. far above any tooth load.
    """
    f = np.asarray(force, dtype=float)
    if np.any(f < 0):
        raise InputError("contact force must be ≥ 0")
    c = math.pi * width * e_star
    with np.errstate(divide="ignore", invalid="ignore"):
        d = f / c * (np.log(4.0 * c * radius_sum / f) - 1.0)
    return np.where(f > 0, d, 0.0)


def total_deflection(
    force: np.ndarray | float,
    k_tot: np.ndarray | float,
    width: float,
    e_star: float,
    radius_sum: np.ndarray | float,
) -> np.ndarray:
    """Seed 002 eq 9: δ(F) = F/K_tot + Johnson δ_c(F) (m), K_tot the series structural stiffness."""
    f = np.asarray(force, dtype=float)
    c = math.pi * width * e_star
    with np.errstate(divide="ignore", invalid="ignore"):
        d = f / np.asarray(k_tot) + f / c * (np.log(4.0 * c * np.asarray(radius_sum) / f) - 1.0)
    return np.where(f > 0, d, 0.0)


def force_from_deflection(
    delta: np.ndarray,
    k_tot: np.ndarray,
    width: float,
    e_star: float,
    radius_sum: np.ndarray,
    iterations: int = 60,
) -> np.ndarray:
    """Invert seed 002 eq 9: the force F ≥ 0 giving deflection δ (vectorised Newton on ln F).

    Returns 0 where δ ≤ 0 (no contact).
    """
    d = np.asarray(delta, dtype=float)
    kt = np.broadcast_to(np.asarray(k_tot, dtype=float), d.shape)
    rs = np.broadcast_to(np.asarray(radius_sum, dtype=float), d.shape)
    c = math.pi * width * e_star
    pos = d > 0
    f = np.where(pos, np.maximum(d, 0.0) * kt * 0.5, 0.0)
    f = np.maximum(f, 1e-9)
    for _ in range(iterations):
        g = f / kt + f / c * (np.log(4.0 * c * rs / f) - 1.0) - d
        dg = 1.0 / kt + (np.log(4.0 * c * rs / f) - 2.0) / c
        step = g / dg
        f_new = np.where(f - step > 0, f - step, f * 0.5)
        if np.all(np.abs(f_new - f) <= 1e-12 * np.maximum(f, 1.0)):
            f = f_new
            break
        f = f_new
    return np.where(pos, f, 0.0)
