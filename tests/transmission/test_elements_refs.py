"""Shaft and disc elements against independent references (issue 12, mutation-testing gaps).

The element matrices are rebuilt here by a second formulation — Gauss quadrature of the
Timoshenko shape functions (Friswell et al., *Dynamics of Rotating Machines*, 2010, §5.4.2,
eqs 5.97-5.98: interpolation of the deflection v and of the section rotation ψ with the shear
parameter Φ; Nelson 1980) — instead of the closed-form coefficients coded in
``geardyn.elements.beam``; the gyroscopic matrix from the gyroscopic work of the rotary inertia
with the rigid disc's sign convention; the disc properties by quadrature over the annulus.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.elements import ShaftSection
from geardyn.elements.beam import shear_coefficient, timoshenko_element, timoshenko_gyroscopic
from geardyn.elements.disc import disc_gyroscopic, rigid_disc, solid_disc_properties
from geardyn.errors import InputError

# seed 002 Table 1 shaft (hollow), and a solid one with another material
HOLLOW = ShaftSection(0.060, 0.045, 210e9, 0.3, 7800.0)
SOLID = ShaftSection(0.080, 0.0, 110e9, 0.34, 8900.0)
IX = [0, 4, 6, 10]  # x–z plane: (x1, θy1, x2, θy2), ψ = θy
IY = [1, 3, 7, 9]  # y–z plane: (y1, θx1, y2, θx2), ψ = −θx
SG = np.array([1.0, -1.0, 1.0, -1.0])


def _phi(length: float, s: ShaftSection) -> float:
    """Shear parameter Φ = 12 E I / (κ G A L²) (Friswell 2010 eq 5.94)."""
    return 12 * s.youngs_modulus * s.second_moment / (s.kappa * s.shear_modulus * s.area
                                                       * length**2)


def _shapes(xi: float, length: float, phi: float) -> tuple[np.ndarray, np.ndarray]:
    """Timoshenko shape functions of v and ψ = rotation of the section, DOF (v1, ψ1, v2, ψ2),
    ξ = z/L (Friswell 2010 eqs 5.97-5.98)."""
    d = 1 + phi
    n_v = np.array([
        1 - 3 * xi**2 + 2 * xi**3 + phi * (1 - xi),
        length * (xi - 2 * xi**2 + xi**3 + phi * (xi - xi**2) / 2),
        3 * xi**2 - 2 * xi**3 + phi * xi,
        length * (-(xi**2) + xi**3 - phi * (xi - xi**2) / 2),
    ]) / d
    n_psi = np.array([
        6 * (xi**2 - xi) / length,
        1 - 4 * xi + 3 * xi**2 + phi * (1 - xi),
        6 * (xi - xi**2) / length,
        -2 * xi + 3 * xi**2 + phi * xi,
    ]) / d
    return n_v, n_psi


def _quadrature_plane(length: float, s: ShaftSection):
    """(K, M_translation, M_rotary) of one bending plane by 8-point Gauss quadrature of the
    energies: K = ∫ E I ψ'ᵀψ' + κ G A (v' − ψ)ᵀ(v' − ψ) dz, M_t = ∫ ρA N_vᵀN_v dz,
    M_r = ∫ ρI N_ψᵀN_ψ dz (derivatives by central differences, h = 1e-6 in ξ)."""
    phi = _phi(length, s)
    x, w = np.polynomial.legendre.leggauss(8)
    k = np.zeros((4, 4))
    mt = np.zeros((4, 4))
    mr = np.zeros((4, 4))
    h = 1e-6
    for xi, wq in zip(0.5 * (x + 1), 0.5 * w * length, strict=True):
        n_v, n_psi = _shapes(xi, length, phi)
        up, dn = _shapes(xi + h, length, phi), _shapes(xi - h, length, phi)
        dv = (up[0] - dn[0]) / (2 * h * length)
        dpsi = (up[1] - dn[1]) / (2 * h * length)
        gam = dv - n_psi
        k += wq * (s.youngs_modulus * s.second_moment * np.outer(dpsi, dpsi)
                   + s.kappa * s.shear_modulus * s.area * np.outer(gam, gam))
        mt += wq * s.density * s.area * np.outer(n_v, n_v)
        mr += wq * s.density * s.second_moment * np.outer(n_psi, n_psi)
    return k, mt, mr


@pytest.mark.parametrize("s", [HOLLOW, SOLID], ids=["hollow", "solid"])
@pytest.mark.parametrize("length", [0.015, 0.1, 0.6])
def test_consistent_element_equals_shape_function_quadrature(s: ShaftSection, length: float):
    """Both bending planes, axial and torsional rods: the 12×12 K and M equal the quadrature of
    the shape functions (Φ from 3e-4 to 2: slender to stubby) to 1e-8 (finite-difference
    derivatives) — the coefficients m1…m6, r1…r4 and the (4 ± Φ), (2 − Φ) terms."""
    k_ref, mt, mr = _quadrature_plane(length, s)
    K, M = timoshenko_element(length, s)
    scale_k, scale_m = np.abs(k_ref).max(), np.abs(mt + mr).max()
    for idx, t in ((IX, np.ones((4, 4))), (IY, np.outer(SG, SG))):
        np.testing.assert_allclose(K[np.ix_(idx, idx)], k_ref * t, rtol=0, atol=1e-8 * scale_k)
        np.testing.assert_allclose(M[np.ix_(idx, idx)], (mt + mr) * t, rtol=0,
                                   atol=1e-12 * scale_m)
    # rods (Petyt 2010 §3.2): E A / L, ρ A L / 6 [2 1; 1 2]; G J / L, ρ J L / 6 [2 1; 1 2]
    rod = np.array([[1.0, -1.0], [-1.0, 1.0]])
    cons = np.array([[2.0, 1.0], [1.0, 2.0]]) / 6
    d = s.outer_diameter**4 - s.inner_diameter**4
    area = math.pi / 4 * (s.outer_diameter**2 - s.inner_diameter**2)
    polar = math.pi / 32 * d
    g = s.youngs_modulus / (2 * (1 + s.poisson_ratio))
    for idx, kk, mm in (([2, 8], s.youngs_modulus * area / length, s.density * area * length),
                        ([5, 11], g * polar / length, s.density * polar * length)):
        np.testing.assert_allclose(K[np.ix_(idx, idx)], kk * rod, rtol=1e-12)
        np.testing.assert_allclose(M[np.ix_(idx, idx)], mm * cons, rtol=1e-12)
    # nothing couples the four groups of DOF
    groups = [IX, IY, [2, 8], [5, 11]]
    mask = np.ones((12, 12), bool)
    for gr in groups:
        mask[np.ix_(gr, gr)] = False
    assert np.abs(K[mask]).max() == 0.0 and np.abs(M[mask]).max() == 0.0


@pytest.mark.parametrize("length", [0.015, 0.3])
def test_gyroscopic_matrix_from_the_gyroscopic_work(length: float):
    """G = ∫ ρJ (N_θxᵀ N_θy − N_θyᵀ N_θx) dz with θy = ψ_x, θx = −ψ_y — the rigid disc's
    convention distributed along the element (``disc_gyroscopic``: row θx gets +I_p θ̇y)."""
    s = HOLLOW
    phi = _phi(length, s)
    x, w = np.polynomial.legendre.leggauss(8)
    g_ref = np.zeros((12, 12))
    rho_j = s.density * math.pi / 32 * (s.outer_diameter**4 - s.inner_diameter**4)
    for xi, wq in zip(0.5 * (x + 1), 0.5 * w * length, strict=True):
        _, n_psi = _shapes(xi, length, phi)
        ty = np.zeros(12)
        ty[IX] = n_psi
        tx = np.zeros(12)
        tx[IY] = -n_psi * SG
        g_ref += wq * rho_j * (np.outer(tx, ty) - np.outer(ty, tx))
    G = timoshenko_gyroscopic(length, s)
    np.testing.assert_allclose(G, g_ref, rtol=0, atol=1e-12 * np.abs(g_ref).max())


def test_rigid_tilt_gyroscopic_moment_equals_a_disc_of_the_same_polar_inertia():
    """Rigid tilt rate β̇ about y of a whole element (x = β(z − L/2), θy = β at both nodes):
    the total gyroscopic moment about x (θx rows + lever arms of the y forces, M_x = −z F_y)
    is that of a rigid disc of I_p = ρ J L (``disc_gyroscopic``), and nothing about y."""
    length = 0.2
    s = HOLLOW
    qd = np.zeros(12)
    qd[[0, 6]] = [-length / 2, length / 2]
    qd[[4, 10]] = 1.0
    f = timoshenko_gyroscopic(length, s) @ qd
    m_x = f[3] + f[9] - length * f[7]
    ip = s.density * s.polar_moment * length
    disc = disc_gyroscopic(ip)
    tilt = np.zeros(6)
    tilt[4] = 1.0
    assert m_x == pytest.approx((disc @ tilt)[3], rel=1e-12)
    assert m_x == pytest.approx(ip, rel=1e-12)
    assert abs(f[4] + f[10] + length * f[6]) < 1e-12 * ip  # M_y = z F_x + θy rows


@pytest.mark.parametrize("length", [0.015, 0.3])
def test_lumped_mass_is_hrz_of_the_quadrature_mass(length: float):
    """HRZ lumping (Hinton, Rock & Zienkiewicz 1976): diagonal of the consistent translational
    mass scaled so that the translations carry ρAL, plus ρIL/2 rotary inertia per rotation;
    rods ρAL/2 and ρJL/2 per node."""
    s = HOLLOW
    _k, mt, _mr = _quadrature_plane(length, s)
    _K, M = timoshenko_element(length, s, mass="lumped")
    assert np.count_nonzero(M - np.diag(np.diag(M))) == 0
    m_el = s.density * s.area * length
    scale = m_el / (mt[0, 0] + mt[2, 2])
    want = np.diag(mt) * scale + np.array([0, 1, 0, 1]) * s.density * s.second_moment * length / 2
    for idx in (IX, IY):
        np.testing.assert_allclose(np.diag(M)[idx], want, rtol=1e-10)
    np.testing.assert_allclose(np.diag(M)[[2, 8]], m_el / 2, rtol=1e-12)
    np.testing.assert_allclose(np.diag(M)[[5, 11]], s.density * s.polar_moment * length / 2,
                               rtol=1e-12)


def test_cowper_shear_coefficient_limits():
    """Cowper (1966) Table 1: solid circle κ = 6(1+ν)/(7+6ν); thin-walled tube (d → D)
    κ = 2(1+ν)/(4+3ν)."""
    for nu in (0.0, 0.3, 0.45):
        assert shear_coefficient(nu, 0.0, 1.0) == pytest.approx(6 * (1 + nu) / (7 + 6 * nu),
                                                                rel=1e-14)
        assert shear_coefficient(nu, 1.0 - 1e-7, 1.0) == pytest.approx(
            2 * (1 + nu) / (4 + 3 * nu), rel=1e-6)


def test_section_properties_closed_form():
    s = ShaftSection(0.05, 0.03, 200e9, 0.25, 7000.0)
    assert s.area == pytest.approx(math.pi * (0.025**2 - 0.015**2), rel=1e-14)
    assert s.second_moment == pytest.approx(math.pi * (0.025**4 - 0.015**4) / 4, rel=1e-14)
    assert s.polar_moment == pytest.approx(math.pi * (0.025**4 - 0.015**4) / 2, rel=1e-14)
    assert s.shear_modulus == pytest.approx(200e9 / 2.5, rel=1e-14)


@pytest.mark.parametrize("bad", [dict(youngs_modulus=0.0), dict(density=0.0),
                                 dict(poisson_ratio=0.5), dict(poisson_ratio=-1.0)])
def test_bad_material_is_an_input_error(bad):
    with pytest.raises(InputError, match=r"^shaft section: need E > 0, density > 0"):
        ShaftSection(0.05, 0.0, **bad)


def test_annular_disc_properties_by_quadrature():
    """m, I_p, I_d of an annular disc by quadrature over (r, z): ∫ρ dV, ∫ρ r² dV,
    ∫ρ (r²/2 + z²) dV (diametral axis through the centre of mass)."""
    ro, ri, wdt, rho = 0.12, 0.03, 0.04, 7850.0
    x, w = np.polynomial.legendre.leggauss(6)
    r = ri + (ro - ri) * 0.5 * (x + 1)
    wr = (ro - ri) * 0.5 * w
    z = wdt * 0.5 * x
    wz = wdt * 0.5 * w
    R, Z = np.meshgrid(r, z, indexing="ij")
    dv = 2 * math.pi * R * np.outer(wr, wz) * rho
    m, ip, idia = solid_disc_properties(ro, ri, wdt, rho)
    assert m == pytest.approx(dv.sum(), rel=1e-12)
    assert ip == pytest.approx((dv * R**2).sum(), rel=1e-12)
    assert idia == pytest.approx((dv * (R**2 / 2 + Z**2)).sum(), rel=1e-12)
    with pytest.raises(InputError, match=r"^disc: need outer_radius > inner_radius ≥ 0"):
        solid_disc_properties(0.03, 0.03, wdt, rho)


def test_rigid_disc_matrix_and_thin_disc_default():
    """Friswell 2010 §5.3: diag(m, m, m, I_d, I_d, I_p), I_d = I_p/2 for a thin disc."""
    np.testing.assert_array_equal(np.diag(rigid_disc(3.0, 0.5)), [3, 3, 3, 0.25, 0.25, 0.5])
    np.testing.assert_array_equal(np.diag(rigid_disc(3.0, 0.5, 0.4)), [3, 3, 3, 0.4, 0.4, 0.5])
    with pytest.raises(InputError, match="mass"):
        rigid_disc(-1.0, 0.5)


def test_element_length_and_mass_kind_are_checked():
    with pytest.raises(InputError, match=r"shaft element length must be > 0 m \(got 0.0\)"):
        timoshenko_element(0.0, HOLLOW)
    with pytest.raises(InputError, match=r"shaft element mass must be one of"):
        timoshenko_element(0.1, HOLLOW, mass="diagonal")
