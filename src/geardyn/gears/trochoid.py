"""Trochoidal root fillet of a rack-generated external tooth (PE stiffness option).

A rack whose tip is rounded with radius ρ (the basic rack's ρ_fP) generates below the involute a
fillet traced by the round: the trochoid (transition curve). With the gear's pitch (rolling)
radius r, the round centre a1 = r − r_f − ρ below the rolling line and b1 from the tooth
centreline at the start of the rolling, the fillet point of normal angle γ ∈ [α_t, π/2] is
(Ma, Song, Pang & Wen 2014, Eng. Fail. Anal. 44, transition curve; the same curve in
Chen & Shao 2011)::

    φ(γ) = (a1 / tan γ + b1) / r
    h(γ) = r sin φ − (a1 / sin γ + ρ) cos(γ − φ)       (half thickness)
    y(γ) = r cos φ − (a1 / sin γ + ρ) sin(γ − φ)       (along the tooth centreline)

γ = π/2 is the root point (on the root circle at the angle θ_f = b1/r from the centreline: the
Sainsot root angle consistent with this fillet) and γ = α_t the junction with the involute,
where the rack's straight flank ends, a1 + ρ sin α_t below the rolling line (roll length
r sin α_t − (a1 + ρ sin α_t)/sin α_t).

b1 follows from the rack flank through the tooth's half thickness X0 = r(θ_b − inv α_t) on the
rolling line: b1 = X0 + a1 tan α_t + ρ / cos α_t (= πm/4 + h_a m tan α + ρ cos α for an
unshifted ISO rack with ρ = c m/(1 − sin α)). Transverse plane; for helical gears the normal
ρ is used in the transverse section (approximation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from geardyn.errors import InputError
from geardyn.gears.geometry import MeshGeometry, inv


@dataclass(frozen=True)
class TrochoidFillet:
    """Rack-generated fillet of one external gear (SI): see the module docstring."""

    pitch_radius: float
    root_radius: float
    rack_tip_radius: float
    a1: float
    b1: float
    pressure_angle: float

    @property
    def root_angle(self) -> float:
        """θ_f = b1 / r (rad): angle between the tooth centreline and the fillet's root point."""
        return self.b1 / self.pitch_radius

    def point(self, gamma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(y, h): centreline coordinate and half thickness (m) at normal angles γ (rad)."""
        g = np.asarray(gamma)
        r, a1 = self.pitch_radius, self.a1
        phi = (a1 / np.tan(g) + self.b1) / r
        arm = a1 / np.sin(g) + self.rack_tip_radius
        return r * np.cos(phi) - arm * np.sin(g - phi), r * np.sin(phi) - arm * np.cos(g - phi)

    def dy_dgamma(self, gamma: np.ndarray) -> np.ndarray:
        """dy/dγ (m/rad) by complex step (exact to rounding)."""
        step = 1e-20
        y, _ = self.point(np.asarray(gamma, dtype=complex) + 1j * step)
        return np.imag(y) / step

    @property
    def junction_radius(self) -> float:
        """Radius (m) where the fillet meets the involute (γ = α_t)."""
        y, h = self.point(np.array(self.pressure_angle))
        return float(np.hypot(y, h))

    def section_at_radius(self, radius: float) -> tuple[float, float]:
        """(y, h) of the fillet point at radius r_f ≤ r ≤ junction radius (dense sampling)."""
        gam = np.linspace(math.pi / 2, self.pressure_angle, 2001)
        y, h = self.point(gam)
        rr = np.hypot(y, h)
        return float(np.interp(radius, rr, y)), float(np.interp(radius, rr, h))


def trochoid_fillet(g: MeshGeometry, gear: int) -> TrochoidFillet:
    """Fillet of gear ``gear`` (0 = a, 1 = b) of ``g`` cut by its basic rack.

    The rack tip radius is the blank's ``rack_tip_radius`` or the full round
    (h_f* − h_a*)·m_n/(1 − sin α_n). Raises :class:`InputError` when the round does not fit
    the root depth, when the fillets of neighbouring teeth would overlap, or when the fillet
    undercuts the involute (rack flank ending below the base circle).
    """
    blank = (g.a, g.b)[gear]
    if blank.internal:
        raise InputError("the trochoid fillet is defined for external (rack-generated) gears")
    r = g.pitch_radius[gear]
    rf = g.root_radius[gear]
    at = g.transverse_pressure_angle
    an = g.normal_pressure_angle
    rho = blank.rack_tip_radius
    if rho is None:
        clearance = blank.dedendum_coef - blank.addendum_coef
        if clearance <= 0:
            raise InputError(
                f"gear pair '{g.label}': trochoid fillet needs a bottom clearance "
                f"(dedendum_coef {blank.dedendum_coef} must exceed addendum_coef "
                f"{blank.addendum_coef}) or an explicit rack_tip_radius"
            )
        rho = clearance * g.normal_module / (1.0 - math.sin(an))
    a1 = r - rf - rho
    if a1 <= 0:
        raise InputError(
            f"gear pair '{g.label}': rack tip radius {rho * 1e3:.3f} mm does not fit the root "
            f"depth r − r_f = {(r - rf) * 1e3:.3f} mm"
        )
    x0 = r * (g.half_angle_base[gear] - float(inv(at)))
    b1 = x0 + a1 * math.tan(at) + rho / math.cos(at)
    fil = TrochoidFillet(r, rf, rho, a1, b1, at)
    if fil.root_angle >= math.pi / blank.teeth:
        raise InputError(
            f"gear pair '{g.label}': trochoid fillets of neighbouring teeth overlap (root angle "
            f"{fil.root_angle:.5f} rad ≥ π/z = {math.pi / blank.teeth:.5f} rad); reduce "
            "rack_tip_radius"
        )
    roll = r * math.sin(at) - (a1 + rho * math.sin(at)) / math.sin(at)
    if roll < 0:
        raise InputError(
            f"gear pair '{g.label}': the trochoid fillet undercuts the involute (rack flank ends "
            f"{-roll * 1e3:.3f} mm of roll below the base circle)"
        )
    return fil
