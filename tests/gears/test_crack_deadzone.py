"""Cracked-tooth compliance (seed 002 eq 14, Chen & Shao dead zone) against a second
formulation: scipy quad of eq 6 along the tooth centreline with the dead-zone section written
out from the model's definition, for an external tooth (crack on the pinion) and a ring tooth;
and the crack acting on the gear it is placed on (surviving mutants of the mutation run)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from geardyn.gears.faults import Crack
from geardyn.gears.geometry import GearBlank, Material, inv, mesh_geometry
from geardyn.gears.pe_stiffness import pair_compliance_curve, tooth_compliance

A20 = math.radians(20.0)
MAT = Material(206e9, 0.3)


def _by_quad(g, gear: int, r_c: float, q: float, angle: float) -> tuple[float, float, float]:  # noqa: ANN001
    """(bending, shear, axial) compliance per unit width with a root crack of depth q at
    ``angle``: section half-thickness h below the crack tip; above it h + min(h_dead, h) with
    the parabola h_dead = h_q + (h_tip − h_q)·s², s the height fraction from the crack tip to
    the tooth tip, h_q = h_root − q cos α_c (crack from the root circle)."""
    blank = (g.a, g.b)[gear]
    rb, rf, ra, a2 = (g.base_radius[gear], g.root_radius[gear], g.tip_radius[gear],
                      g.half_angle_base[gear])
    e, gm = MAT.youngs_modulus, MAT.shear_modulus
    if not blank.internal:
        def th(r: float) -> float:
            return a2 - inv(math.acos(rb / r))

        def c_of(r: float) -> float:
            return r * math.cos(th(r)) - rf * math.cos(th(rf))

        ac = math.acos(rb / r_c)
        beta = math.tan(ac) - a2
    else:
        z = blank.teeth

        def th(r: float) -> float:
            return math.pi / z - a2 + inv(math.acos(rb / r))

        def c_of(r: float) -> float:
            return rf * math.cos(th(rf)) - r * math.cos(th(r))

        beta = th(r_c) + math.acos(rb / r_c)
    h_root = rf * math.sin(th(rf))
    h_q = h_root - q * math.cos(angle)
    c_tip, h_tip = c_of(ra), ra * math.sin(th(ra))
    c_p, h_c = c_of(r_c), r_c * math.sin(th(r_c))

    def width(r: float) -> float:
        h = r * math.sin(th(r))
        s = min(max(c_of(r) / c_tip, 0.0), 1.0)
        return h + min(h_q + (h_tip - h_q) * s**2, h)

    def dy(r: float) -> float:
        d = 1e-9
        return abs(c_of(r + d) - c_of(r - d)) / (2 * d)

    lo, hi = sorted((rf, r_c))
    cb, sb = math.cos(beta), math.sin(beta)
    kb = quad(lambda r: 12 * (cb * (c_p - c_of(r)) - sb * h_c) ** 2 / (e * width(r) ** 3) * dy(r),
              lo, hi, epsrel=1e-11, limit=200)[0]
    ks = quad(lambda r: 1.2 * cb**2 / (gm * width(r)) * dy(r), lo, hi, epsrel=1e-11)[0]
    ka = quad(lambda r: sb**2 / (e * width(r)) * dy(r), lo, hi, epsrel=1e-11)[0]
    return kb, ks, ka


@pytest.mark.parametrize("angle_deg", [30.0, 60.0])
def test_cracked_external_tooth_against_quadrature(angle_deg: float) -> None:
    bl = GearBlank(62, rim_radius=0.0175, material=MAT)
    g = mesh_geometry(bl, bl, 0.002, A20, 0.02)  # root circle above the base circle
    assert g.root_radius[0] > g.base_radius[0]
    crack = Crack(gear="a", depth=0.8e-3, angle=math.radians(angle_deg))
    for r_c in (0.0605, 0.062, 0.0635):
        tc = tooth_compliance(g, 0, np.array([r_c]), crack.depth, crack)
        kb, ks, ka = _by_quad(g, 0, r_c, crack.depth, crack.angle)
        assert float(tc.bending[0]) == pytest.approx(kb, rel=1e-3, abs=0)
        assert float(tc.shear[0]) == pytest.approx(ks, rel=1e-3, abs=0)
        assert float(tc.axial[0]) == pytest.approx(ka, rel=1e-3, abs=0)


def test_cracked_ring_tooth_against_quadrature() -> None:
    g = mesh_geometry(GearBlank(32, form_radius=0.0, material=MAT),
                      GearBlank(83, internal=True, material=MAT), 0.004, A20, 0.03)
    crack = Crack(gear="b", depth=1.0e-3, angle=math.radians(45.0))
    for r_c in np.linspace(g.tip_radius[1] + 3e-4, g.tip_radius[1] + 5e-3, 3):
        tc = tooth_compliance(g, 1, np.array([r_c]), crack.depth, crack)
        kb, ks, ka = _by_quad(g, 1, float(r_c), crack.depth, crack.angle)
        assert float(tc.bending[0]) == pytest.approx(kb, rel=1e-3, abs=0)
        assert float(tc.shear[0]) == pytest.approx(ks, rel=1e-3, abs=0)
        assert float(tc.axial[0]) == pytest.approx(ka, rel=1e-3, abs=0)


def test_crack_acts_on_its_own_gear_only() -> None:
    """A crack on the pinion raises exactly the pinion tooth's compliance in the pair curve,
    one on the wheel exactly the wheel's."""
    g = mesh_geometry(GearBlank(30, material=MAT), GearBlank(45, material=MAT), 0.003, A20, 0.02)
    u = np.linspace(g.u_start, g.u_end, 7)
    ra, rb_ = g.contact_radii(u)
    c0 = pair_compliance_curve(g, u)
    for side, r, i in (("a", ra, 0), ("b", rb_, 1)):
        cr = Crack(gear=side, depth=0.8e-3)
        dc = pair_compliance_curve(g, u, cr, cr.depth) - c0
        ref = (tooth_compliance(g, i, r, cr.depth, cr).total - tooth_compliance(g, i, r).total)
        np.testing.assert_allclose(dc, ref, rtol=1e-9)
        assert np.all(dc > 0)
