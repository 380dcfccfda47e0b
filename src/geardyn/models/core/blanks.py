"""Gear sizes and blank mass properties used as defaults by the graph builder (SI units).

* pitch radius r = m z / 2 (mean module for bevel wheels), base radius r_b = r cos α;
* an external wheel is a solid steel disc of pitch radius and face width b:
  m = ρ π r² b, J = m r²/2, J_d = m (3 r² + b²)/12 (about a diameter);
* an internal wheel (ring) is an annulus from its pitch radius to r + 4 m (a rim of about three
  modules beyond the tooth root): m = ρ π (R² − r²) b, J = m (R² + r²)/2,
  J_d = m (3 (R² + r²) + b²)/12;
* transverse contact ratio of standard-addendum (h_a = m) spur gears (ISO 21771 eq 103):
  external ε = [√(r_a1² − r_b1²) + √(r_a2² − r_b2²) − (r_1 + r_2) sin α] / (π m cos α);
  internal (ring 2) ε = [√(r_a1² − r_b1²) − √(r_a2² − r_b2²) + (r_2 − r_1) sin α] / (π m cos α)
  with r_a2 = r_2 − m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Blank:
    """Mass (kg), polar and diametral inertia (kg·m²) of one gear blank."""

    mass: float
    inertia: float
    diametral: float


def wheel_blank(module: float, teeth: int, face_width: float, density: float,
                internal: bool) -> Blank:
    """Blank of a wheel with ``teeth`` teeth (see the module docstring)."""
    r = module * teeth / 2
    if internal:
        big = r + 4 * module
        m = density * math.pi * (big**2 - r**2) * face_width
        return Blank(m, m * (big**2 + r**2) / 2, m * (3 * (big**2 + r**2) + face_width**2) / 12)
    m = density * math.pi * r**2 * face_width
    return Blank(m, m * r**2 / 2, m * (3 * r**2 + face_width**2) / 12)


def disc_blank(radius: float, face_width: float, density: float) -> Blank:
    """Solid disc (a carrier plate by default)."""
    m = density * math.pi * radius**2 * face_width
    return Blank(m, m * radius**2 / 2, m * (3 * radius**2 + face_width**2) / 12)


def contact_ratio(module: float, teeth_a: int, teeth_b: int, alpha: float,
                  internal_b: bool = False) -> float:
    """Transverse contact ratio of standard spur gears (ISO 21771 eq 103)."""
    r1, r2 = module * teeth_a / 2, module * teeth_b / 2
    rb1, rb2 = r1 * math.cos(alpha), r2 * math.cos(alpha)
    g1 = math.sqrt((r1 + module) ** 2 - rb1**2)
    pb = math.pi * module * math.cos(alpha)
    if internal_b:
        g2 = math.sqrt((r2 - module) ** 2 - rb2**2)
        return (g1 - g2 + (r2 - r1) * math.sin(alpha)) / pb
    g2 = math.sqrt((r2 + module) ** 2 - rb2**2)
    return (g1 + g2 - (r1 + r2) * math.sin(alpha)) / pb
