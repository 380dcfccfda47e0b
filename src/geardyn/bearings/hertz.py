"""Hertzian contact constants for rolling bearings (SI units).

Point contact (balls): the load–deflection law Q = K δ^1.5 with, for principal radii R_x
(rolling direction) and R_y (transverse), 1/R = 1/R_x + 1/R_y and ellipticity κ = a/b solving
Harris's curvature-difference relation (Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed.,
§6.2)::

    F(ρ) = (1/R_x − 1/R_y)/(1/R_x + 1/R_y) = ((κ²+1) ℰ − 2 ℱ) / ((κ²−1) ℰ)

with ℱ, ℰ the complete elliptic integrals of the first and second kind (parameter 1 − 1/κ²);
the approach is (Hamrock & Brewe 1983, exact when κ, ℱ, ℰ are exact)::

    δ = ℱ [ (9 / (2 ℰ R)) (Q / (π κ E'))² ]^(1/3),  E' = 2 / ((1−ν₁²)/E₁ + (1−ν₂²)/E₂)

so K = π κ E' √(2 ℰ R / 9) / ℱ^1.5. Inner and outer contacts in series:
K = [K_i^(−2/3) + K_o^(−2/3)]^(−3/2).

Line contact (rollers): Palmgren's empirical law for steel, δ = 3.84·10⁻⁵ Q^0.9 / l^0.8 (mm, N)
per contact (Harris & Kotzalas eq 6.40), i.e. Q = K δ^(10/9) for both contacts in series.
"""

from __future__ import annotations

import math

from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from geardyn.errors import InputError


def reduced_modulus(e1: float, nu1: float, e2: float, nu2: float) -> float:
    """E' = 2 / ((1−ν₁²)/E₁ + (1−ν₂²)/E₂) (Pa)."""
    return 2.0 / ((1 - nu1 * nu1) / e1 + (1 - nu2 * nu2) / e2)


def ellipticity(rx: float, ry: float) -> tuple[float, float, float]:
    """(κ, ℱ, ℰ) of a point contact with principal relative radii ``rx`` ≤ ``ry`` (m)."""
    if not (rx > 0 and ry > 0):
        raise InputError(f"Hertz contact: radii must be > 0 (got {rx}, {ry})")
    if ry < rx:
        rx, ry = ry, rx
    f_rho = (1 / rx - 1 / ry) / (1 / rx + 1 / ry)
    if f_rho < 1e-12:
        return 1.0, math.pi / 2, math.pi / 2

    def resid(k: float) -> float:
        m = 1.0 - 1.0 / (k * k)
        return ((k * k + 1) * ellipe(m) - 2 * ellipk(m)) / ((k * k - 1) * ellipe(m)) - f_rho

    k = brentq(resid, 1.0 + 1e-9, 1e4, xtol=1e-14, rtol=1e-14)
    m = 1.0 - 1.0 / (k * k)
    return k, float(ellipk(m)), float(ellipe(m))


def point_contact_stiffness(rx: float, ry: float, e_prime: float) -> float:
    """K (N/m^1.5) of Q = K δ^1.5 for one point contact."""
    k, ff, ee = ellipticity(rx, ry)
    r = 1.0 / (1.0 / rx + 1.0 / ry)
    return math.pi * k * e_prime * math.sqrt(2.0 * ee * r / 9.0) / ff**1.5


def series_point(k_inner: float, k_outer: float) -> float:
    """Inner + outer point contacts in series (exponent 1.5)."""
    return (k_inner ** (-2.0 / 3.0) + k_outer ** (-2.0 / 3.0)) ** -1.5


def ball_race_stiffness(
    ball_diameter: float,
    pitch_diameter: float,
    inner_conformity: float,
    outer_conformity: float,
    e_prime: float,
    contact_angle: float = 0.0,
) -> tuple[float, float, float]:
    """(K_inner, K_outer, K_total) in N/m^1.5 of a ball between grooved races."""
    D, dm = ball_diameter, pitch_diameter
    if not (0 < D < dm and inner_conformity > 0.5 and outer_conformity > 0.5):
        raise InputError(
            "ball bearing: need 0 < ball_diameter < pitch_diameter and conformities > 0.5"
        )
    g = D * math.cos(contact_angle) / dm
    # curvatures (1/m): ball 2/D in both directions; races along rolling (x) and across (y)
    rx_i = 1.0 / (2 / D + 2 / D * g / (1 - g))
    ry_i = 1.0 / (2 / D - 1 / (inner_conformity * D))
    rx_o = 1.0 / (2 / D - 2 / D * g / (1 + g))
    ry_o = 1.0 / (2 / D - 1 / (outer_conformity * D))
    ki = point_contact_stiffness(rx_i, ry_i, e_prime)
    ko = point_contact_stiffness(rx_o, ry_o, e_prime)
    return ki, ko, series_point(ki, ko)


def roller_race_stiffness(effective_length: float) -> float:
    """K (N/m^(10/9)) of Q = K δ^(10/9), inner + outer line contacts in series (Palmgren)."""
    if not effective_length > 0:
        raise InputError(f"roller effective length must be > 0 m (got {effective_length})")
    l_mm = effective_length * 1e3
    # δ_total [mm] = 2 · 3.84e-5 · Q^0.9 / l^0.8  →  Q = (δ_mm l^0.8 / 7.68e-5)^(1/0.9)
    c = 7.68e-5 / l_mm**0.8  # mm / N^0.9
    # δ in m: δ_mm = 1e3 δ → Q = (1e3 δ / c)^(10/9)
    return (1e3 / c) ** (10.0 / 9.0)
