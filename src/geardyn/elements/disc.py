"""Rigid disc (gear wheel body) lumped at a node: mass and inertia (SI).

Seed 002 §2.1 models each gear wheel as a rigid disc on its shaft node; the nodal mass matrix is
the standard rigid-disc one of rotordynamics (e.g. Friswell et al., *Dynamics of Rotating
Machines*, 2010, §5.3), I_d = I_p/2 for a thin disc.
"""

from __future__ import annotations

import math

import numpy as np

from geardyn.errors import InputError


def rigid_disc(
    mass: float, polar_inertia: float, diametral_inertia: float | None = None
) -> np.ndarray:
    """6×6 nodal mass matrix of a rigid disc: m on x, y, z; I_d on θx, θy; I_p on θz.

    ``diametral_inertia`` defaults to I_p / 2 (thin disc)."""
    if not (mass >= 0 and polar_inertia >= 0):
        raise InputError("rigid disc: mass and polar_inertia must be ≥ 0")
    idia = polar_inertia / 2.0 if diametral_inertia is None else diametral_inertia
    return np.diag([mass, mass, mass, idia, idia, polar_inertia])


def solid_disc_properties(
    outer_radius: float, inner_radius: float, width: float, density: float
) -> tuple[float, float, float]:
    """Mass (kg), polar and diametral inertia (kg·m²) of an annular disc of ``width`` (m)."""
    if not (outer_radius > inner_radius >= 0 and width > 0 and density > 0):
        raise InputError("disc: need outer_radius > inner_radius ≥ 0, width > 0, density > 0")
    m = density * math.pi * (outer_radius**2 - inner_radius**2) * width
    ip = 0.5 * m * (outer_radius**2 + inner_radius**2)
    idia = 0.25 * m * (outer_radius**2 + inner_radius**2) + m * width**2 / 12.0
    return m, ip, idia


def disc_gyroscopic(polar_inertia: float) -> np.ndarray:
    """6×6 nodal gyroscopic matrix of a rigid disc per rad/s of spin: (θx, θy) rows
    I_p [[0, 1], [−1, 0]]."""
    g = np.zeros((6, 6))
    g[3, 4] = polar_inertia
    g[4, 3] = -polar_inertia
    return g
