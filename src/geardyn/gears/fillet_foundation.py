"""Fillet-foundation (gear body) compliance of Sainsot, Velex & Duverger (2004), seed 002 eq 7.

    1/K_f = cos²(β)/(E δz) · [L*(u_f/S_f)² + M*(u_f/S_f) + P*(1 + Q* tan²β)]

β is the angle of the contact force to the tooth perpendicular (seed 002's b_eff), u_f the
distance along the tooth centreline from the root circle to the point where the force line
crosses the centreline, S_f = 2 r_f θ_f the chordal tooth thickness at the root circle, and
X* = A/θ_f² + B h² + C h/θ_f + D/θ_f + E h + F with the coefficients of seed 002 Table 5
(Appendix 3). Seed 002 writes the ratio as R_f/R_a; Sainsot's original defines it as
h_fi = r_f/r_int with r_int the bore (rim) radius, which is what is used here (R_a is not in
the seed's nomenclature). θ_f in radians.
"""

from __future__ import annotations

import numpy as np

#: Seed 002 Table 5 (Appendix 3): rows L*, M*, P*, Q*; columns A..F.
SAINSOT_COEFFICIENTS: dict[str, tuple[float, float, float, float, float, float]] = {
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.3e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}


def sainsot_coefficient(name: str, theta_f: float, h_fi: float) -> float:
    """X* of seed 002 eq 3.2 for X ∈ {L, M, P, Q}; θ_f (rad), h_fi = r_f/r_int."""
    a, b, c, d, e, f = SAINSOT_COEFFICIENTS[name]
    return a / theta_f**2 + b * h_fi**2 + c * h_fi / theta_f + d / theta_f + e * h_fi + f


def fillet_foundation_compliance(
    beta: np.ndarray,
    u_f: np.ndarray,
    s_f: float,
    theta_f: float,
    h_fi: float,
    youngs_modulus: float,
    width: float = 1.0,
) -> np.ndarray:
    """1/K_f (m/N) of seed 002 eq 7 for force angles ``beta`` (rad) and lever ``u_f`` (m).

    ``width`` = δz (m); the result scales as 1/width.
    """
    lc = sainsot_coefficient("L", theta_f, h_fi)
    mc = sainsot_coefficient("M", theta_f, h_fi)
    pc = sainsot_coefficient("P", theta_f, h_fi)
    qc = sainsot_coefficient("Q", theta_f, h_fi)
    beta = np.asarray(beta, dtype=float)
    ratio = np.asarray(u_f, dtype=float) / s_f
    return (
        np.cos(beta) ** 2
        / (youngs_modulus * width)
        * (lc * ratio**2 + mc * ratio + pc * (1.0 + qc * np.tan(beta) ** 2))
    )
