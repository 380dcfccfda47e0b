"""Timoshenko beam element for shafts, 2 nodes × 6 DOF (x, y, z, θx, θy, θz), axis along z.

Bending uses the shear-deformable (Timoshenko) element with cubic interpolation and shear
parameter Φ = 12 E I / (κ G A L²) (Przemieniecki 1968; Friswell et al., *Dynamics of Rotating
Machines*, 2010, §5.4; Nelson 1980): stiffness

    K_b = E I / ((1+Φ) L³) · [[12, 6L, −12, 6L], [6L, (4+Φ)L², −6L, (2−Φ)L²], ...]

and the consistent translational + rotary-inertia mass matrices with their Φ-dependent
coefficients. Axial and torsional parts are the linear two-node rod elements. Gyroscopic
matrix per unit spin speed: :func:`timoshenko_gyroscopic` (Nelson 1980: the rotary-inertia
shape integrals with the polar density ρJ = 2ρI, skew between the two bending planes).

Lumped (diagonal) mass, ``mass="lumped"``: HRZ diagonal scaling (Hinton, Rock & Zienkiewicz,
*Earthq. Eng. Struct. Dyn.* 4, 1976, 245-249; Cook et al., *Concepts and Applications of Finite
Element Analysis*, 4th ed., 2002, §11.3): the diagonal of the consistent translational mass is
scaled so that each direction carries the element mass ρAL, the rotation diagonal by the same
factor (ρAL³/78 per node when Φ = 0); rotary inertia ρIL/2 and, for the rods, ρAL/2 and ρJL/2
per node (HRZ of the rotary-inertia and rod matrices, equal to their row sums). The lumped
element's highest axial frequency is 2c/L instead of √12 c/L (c = √(E/ρ)): the explicit step
grows by √3 when that mode bounds it.

Sign conventions: in the x–z plane θy = +dx/dz, in the y–z plane θx = −dy/dz.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from geardyn.errors import InputError


def shear_coefficient(poisson_ratio: float, inner_diameter: float, outer_diameter: float) -> float:
    """Cowper (1966) shear coefficient κ of a hollow circular section."""
    m = inner_diameter / outer_diameter
    nu = poisson_ratio
    m2 = (1.0 + m * m) ** 2
    return 6.0 * (1.0 + nu) * m2 / ((7.0 + 6.0 * nu) * m2 + (20.0 + 12.0 * nu) * m * m)


@dataclass(frozen=True)
class ShaftSection:
    """Hollow circular shaft section and material (SI: m, Pa, kg/m³)."""

    outer_diameter: float
    inner_diameter: float = 0.0
    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    density: float = 7800.0

    def __post_init__(self) -> None:
        if not (self.outer_diameter > 0 and 0 <= self.inner_diameter < self.outer_diameter):
            raise InputError(
                "shaft section: need 0 ≤ inner_diameter < outer_diameter "
                f"(got {self.inner_diameter}, {self.outer_diameter})"
            )
        if not (self.youngs_modulus > 0 and self.density > 0 and -1 < self.poisson_ratio < 0.5):
            raise InputError("shaft section: need E > 0, density > 0, −1 < ν < 0.5")

    @property
    def area(self) -> float:
        return math.pi / 4.0 * (self.outer_diameter**2 - self.inner_diameter**2)

    @property
    def second_moment(self) -> float:
        """Diametral second moment of area I (m⁴)."""
        return math.pi / 64.0 * (self.outer_diameter**4 - self.inner_diameter**4)

    @property
    def polar_moment(self) -> float:
        """Polar second moment J = 2 I (m⁴)."""
        return 2.0 * self.second_moment

    @property
    def shear_modulus(self) -> float:
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def kappa(self) -> float:
        return shear_coefficient(self.poisson_ratio, self.inner_diameter, self.outer_diameter)


#: Mass options of :func:`timoshenko_element`.
MASS_KINDS = ("consistent", "lumped")


def _bending(length: float, s: ShaftSection, lumped: bool = False
             ) -> tuple[np.ndarray, np.ndarray]:
    """4×4 stiffness and mass of the Timoshenko element in one plane, DOF (v1, ψ1, v2, ψ2)
    with ψ = dv/dz; ``lumped``: HRZ diagonal mass (module docstring)."""
    L = length
    E, I, A, rho = s.youngs_modulus, s.second_moment, s.area, s.density
    phi = 12.0 * E * I / (s.kappa * s.shear_modulus * A * L * L)
    k = E * I / ((1.0 + phi) * L**3)
    K = k * np.array(
        [
            [12.0, 6 * L, -12.0, 6 * L],
            [6 * L, (4 + phi) * L * L, -6 * L, (2 - phi) * L * L],
            [-12.0, -6 * L, 12.0, -6 * L],
            [6 * L, (2 - phi) * L * L, -6 * L, (4 + phi) * L * L],
        ]
    )
    p2 = phi * phi
    m1 = 13 / 35 + 7 * phi / 10 + p2 / 3
    m2 = (11 / 210 + 11 * phi / 120 + p2 / 24) * L
    m3 = 9 / 70 + 3 * phi / 10 + p2 / 6
    m4 = -(13 / 420 + 3 * phi / 40 + p2 / 24) * L
    m5 = (1 / 105 + phi / 60 + p2 / 120) * L * L
    m6 = -(1 / 140 + phi / 60 + p2 / 120) * L * L
    Mt = (rho * A * L / (1 + phi) ** 2) * np.array(
        [[m1, m2, m3, m4], [m2, m5, -m4, m6], [m3, -m4, m1, -m2], [m4, m6, -m2, m5]]
    )
    if lumped:
        # HRZ: translation diagonal scaled to ρAL/2 per node, rotation by the same factor
        scale = 0.5 * (1 + phi) ** 2 / m1
        mt = rho * A * L / (1 + phi) ** 2 * scale
        return K, np.diag([mt * m1, mt * m5, mt * m1, mt * m5]) + np.diag(
            [0.0, 0.5 * rho * I * L, 0.0, 0.5 * rho * I * L])
    r1 = 6 / 5
    r2 = (1 / 10 - phi / 2) * L
    r3 = (2 / 15 + phi / 6 + p2 / 3) * L * L
    r4 = (-1 / 30 - phi / 6 + p2 / 6) * L * L
    Mr = (rho * I / ((1 + phi) ** 2 * L)) * np.array(
        [[r1, r2, -r1, r2], [r2, r3, -r2, r4], [-r1, -r2, r1, -r2], [r2, r4, -r2, r3]]
    )
    return K, Mt + Mr


def timoshenko_element(length: float, section: ShaftSection, mass: str = "consistent"
                       ) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and mass matrices (12×12, SI) of a shaft element of ``length`` (m); ``mass``
    "consistent" or "lumped" (HRZ diagonal, module docstring).

    DOF order: node 1 (x, y, z, θx, θy, θz), node 2 (same)."""
    if not length > 0:
        raise InputError(f"shaft element length must be > 0 m (got {length})")
    if mass not in MASS_KINDS:
        raise InputError(f"shaft element mass must be one of {MASS_KINDS} (got {mass!r})")
    lumped = mass == "lumped"
    s = section
    L = length
    K = np.zeros((12, 12))
    M = np.zeros((12, 12))
    Kb, Mb = _bending(L, s, lumped)
    # x–z plane: (x1, θy1, x2, θy2), ψ = θy
    ix = [0, 4, 6, 10]
    K[np.ix_(ix, ix)] += Kb
    M[np.ix_(ix, ix)] += Mb
    # y–z plane: (y1, −θx1, y2, −θx2)
    iy = [1, 3, 7, 9]
    sg = np.array([1.0, -1.0, 1.0, -1.0])
    T = np.outer(sg, sg)
    K[np.ix_(iy, iy)] += Kb * T
    M[np.ix_(iy, iy)] += Mb * T
    rod = np.array([[1.0, -1.0], [-1.0, 1.0]])
    rodm = np.eye(2) / 2.0 if lumped else np.array([[2.0, 1.0], [1.0, 2.0]]) / 6.0
    iz = [2, 8]
    K[np.ix_(iz, iz)] += s.youngs_modulus * s.area / L * rod
    M[np.ix_(iz, iz)] += s.density * s.area * L * rodm
    it = [5, 11]
    K[np.ix_(it, it)] += s.shear_modulus * s.polar_moment / L * rod
    M[np.ix_(it, it)] += s.density * s.polar_moment * L * rodm
    return K, M


def timoshenko_gyroscopic(length: float, section: ShaftSection) -> np.ndarray:
    """Gyroscopic matrix G (12×12, per rad/s of spin) of the element: M q̈ + Ω G q̇ + K q = 0.

    The section's gyroscopic moments are (M_x, M_y) = ρJ Ω (θ̇y, −θ̇x) per unit length; with
    θy = ψ_x and θx = −ψ_y interpolated like the rotary inertia, G couples the planes with
    ±∫ρJ N_ψᵀ N_ψ dz = ±2 M_rotary (skew-symmetric)."""
    L = length
    s = section
    E, I, A = s.youngs_modulus, s.second_moment, s.area
    phi = 12.0 * E * I / (s.kappa * s.shear_modulus * A * L * L)
    p2 = phi * phi
    r1 = 6 / 5
    r2 = (1 / 10 - phi / 2) * L
    r3 = (2 / 15 + phi / 6 + p2 / 3) * L * L
    r4 = (-1 / 30 - phi / 6 + p2 / 6) * L * L
    Mr = (s.density * I / ((1 + phi) ** 2 * L)) * np.array(
        [[r1, r2, -r1, r2], [r2, r3, -r2, r4], [-r1, -r2, r1, -r2], [r2, r4, -r2, r3]]
    )
    G = np.zeros((12, 12))
    ix = [0, 4, 6, 10]
    iy = [1, 3, 7, 9]
    sg = np.array([1.0, -1.0, 1.0, -1.0])
    G[np.ix_(ix, iy)] = 2.0 * Mr * sg[None, :]
    G[np.ix_(iy, ix)] = -(2.0 * Mr * sg[:, None])
    return G
