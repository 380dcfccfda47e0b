"""Crack depth laws, spall footprint, Sainsot rim defaults, mean stiffness and table lookup,
against closed forms and an independent quadrature (gaps found by the mutation run, see
docs/validation.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from geardyn.gears.faults import Crack, Spall
from geardyn.gears.fillet_foundation import fillet_foundation_compliance
from geardyn.gears.geometry import GearBlank, inv, mesh_geometry
from geardyn.gears.pe_stiffness import (
    mean_stiffness,
    mesh_stiffness,
    pair_compliance_curve,
    tooth_compliance,
)

from .seed002 import A20, seed002_low

B = 0.025


@pytest.mark.parametrize("width", [None, 0.01])
def test_crack_depth_laws_closed_form(width) -> None:  # noqa: ANN001
    z = np.array([0.0, 0.0025, 0.005, 0.0075, 0.0099, 0.012, 0.02])
    w = B if width is None else width
    s = np.clip(z / w, 0, None)
    q0 = 1e-3
    uni = Crack(depth=q0, width=width).depth_at(z, B)
    np.testing.assert_allclose(uni, np.where(s <= 1, q0, 0.0), rtol=0, atol=1e-15)
    lin = Crack(depth=q0, width=width, law="linear").depth_at(z, B)
    np.testing.assert_allclose(lin, q0 * np.clip(1 - s, 0, 1), rtol=1e-12, atol=1e-15)
    par = Crack(depth=q0, width=width, law="parabolic").depth_at(z, B)
    np.testing.assert_allclose(par, q0 * np.sqrt(np.clip(1 - s, 0, 1)), rtol=1e-12, atol=1e-15)
    assert par.dtype == float and Crack(depth=q0).depth_at([0, 1e-3], B).shape == (2,)
    assert np.all(Crack(depth=q0, width=0.0).depth_at(z, B) == 0.0)


def test_spall_footprint_edges() -> None:
    sp = Spall(radius=0.08, radial_width=0.002, axial_position=0.01, axial_length=0.004)
    r = np.array([0.0789, 0.07901, 0.08, 0.08099, 0.0811])
    assert list(sp.covers(r, np.full(5, 0.01), B)) == [False, True, True, True, False]
    zz = np.array([0.0079, 0.00801, 0.01199, 0.0121])
    assert list(sp.covers(np.full(4, 0.08), zz, B)) == [False, True, True, False]
    whole = Spall(radius=0.08, radial_width=0.002)  # axial None: the whole face, centred
    assert whole.covers(np.array([0.08, 0.08]), np.array([0.0, B]), B).all()
    assert not whole.covers(np.array([0.08]), np.array([B * 1.001]), B).any()


def _fillet_by_hand(g, gear: int, r: np.ndarray, h_fi: float) -> np.ndarray:  # noqa: ANN001
    """Seed 002 eq 7 with θ_f, S_f, u_f, β of the involute tooth evaluated by hand."""
    rb, rf, a2 = g.base_radius[gear], g.root_radius[gear], g.half_angle_base[gear]
    blank = (g.a, g.b)[gear]
    ac = np.arccos(rb / r)
    if not blank.internal:
        th_f = a2 - inv(math.acos(rb / rf)) if rf > rb else a2
        th_c = a2 - inv(ac)
        beta = np.tan(ac) - a2
        u = r * np.cos(th_c) - r * np.sin(th_c) * np.tan(beta) - rf
    else:
        z = blank.teeth
        th_f = math.pi / z - a2 + inv(math.acos(rb / rf))
        th_c = math.pi / z - a2 + inv(ac)
        beta = th_c + ac
        u = rf - r * np.cos(th_c) - r * np.sin(th_c) * np.tan(beta)
    return fillet_foundation_compliance(beta, np.maximum(u, 0), 2 * rf * th_f, th_f, h_fi,
                                        blank.material.youngs_modulus)


def test_sainsot_rim_ratio_defaults() -> None:
    """h_fi = r_f/r_int: the bore (rim_radius) when given, else max(r_f − 3.5 m_n, r_f/4);
    ring: r_f/(r_f − t) with the rim thickness t = outer rim − r_f, default 3.5 m_n."""
    m = 0.003
    g = mesh_geometry(GearBlank(42, form_radius=0.0), GearBlank(90, internal=True), m, A20, B)
    r = np.linspace(g.form_radius[0] + 1e-4, g.tip_radius[0] - 1e-4, 5)
    rf = g.root_radius[0]
    ref = _fillet_by_hand(g, 0, r, rf / max(rf - 3.5 * m, 0.25 * rf))
    np.testing.assert_allclose(tooth_compliance(g, 0, r).fillet, ref, rtol=1e-12)
    rr = np.linspace(g.tip_radius[1] + 1e-4, g.root_radius[1] - 2e-3, 5)
    rfr = g.root_radius[1]
    ref = _fillet_by_hand(g, 1, rr, rfr / (rfr - 3.5 * m))
    np.testing.assert_allclose(tooth_compliance(g, 1, rr).fillet, ref, rtol=1e-12)
    g2 = mesh_geometry(GearBlank(10, profile_shift=0.45), GearBlank(30), m, A20, B)
    rf2 = g2.root_radius[0]
    assert rf2 - 3.5 * m < 0.25 * rf2  # small pinion: the r_f/4 floor applies
    r2 = np.array([g2.tip_radius[0] - 2e-4])
    np.testing.assert_allclose(tooth_compliance(g2, 0, r2).fillet,
                               _fillet_by_hand(g2, 0, r2, 4.0), rtol=1e-12)
    # the fillet formula's default width is δz = 1 m
    assert fillet_foundation_compliance(0.3, 0.004, 0.006, 0.1, 2.0, 2e11) == pytest.approx(
        2.0 * fillet_foundation_compliance(0.3, 0.004, 0.006, 0.1, 2.0, 2e11, 2.0), rel=1e-14,
        abs=0)


def test_mean_stiffness_against_quadrature() -> None:
    """Mean over a mesh cycle = (b/p_bt) ∫ k_pair(u) du over the path of contact (each pair
    crosses the whole path once per ε_α cycles), by scipy quad on the PE pair compliance."""
    g = seed002_low()
    ref, _ = quad(lambda u: 1.0 / float(pair_compliance_curve(g, np.array([u]))[0]),
                  g.u_start, g.u_end, epsabs=0, epsrel=1e-10, limit=200)
    ref *= g.face_width / g.base_pitch
    assert mean_stiffness(g) == pytest.approx(ref, rel=2e-3)


def test_table_lookup_periodic_and_exact_at_samples() -> None:
    t = mesh_stiffness(seed002_low(), n_per_cycle=32)
    assert t.at(t.mesh_cycle[5]) == pytest.approx(t.total[5], rel=1e-14)
    xi = np.array([0.123, 0.5, 0.97])
    np.testing.assert_allclose(t.at(xi + 3.0), t.at(xi), rtol=1e-12)
    mid = 0.5 * (t.mesh_cycle[7] + t.mesh_cycle[8])
    assert t.at(mid) == pytest.approx(0.5 * (t.total[7] + t.total[8]), rel=1e-12)
    assert t.at([0.25]).dtype == float


@pytest.mark.parametrize("n_slices,tol", [(8, 1.5e-3), (24, 2e-4)])
def test_helical_mean_stiffness_against_quadrature(n_slices: int, tol: float) -> None:
    """Every slice of a helical pair crosses the whole transverse path once per pair, so the
    mean over a mesh cycle is (b/p_bt) ∫ k'(u) du as for a spur pair (to the slicing error);
    and the table is smooth (no slice-sized steps: adjacent samples differ by < 3 % of the
    mean)."""
    from .seed002 import seed002_high

    g = seed002_high()
    ref, _ = quad(lambda u: 1.0 / float(pair_compliance_curve(g, np.array([u]))[0]),
                  g.u_start, g.u_end, epsabs=0, epsrel=1e-10, limit=200)
    ref *= g.face_width / g.base_pitch
    t = mesh_stiffness(g, n_per_cycle=128, n_slices=n_slices)
    # measured 4.7e-4 (8 slices), 5e-5 (24); half-slice shifts of the slice centres or of the
    # contact spread give 3e-3 / 3e-4
    assert t.total.mean() == pytest.approx(ref, rel=tol)
    assert np.abs(np.diff(t.total)).max() < 0.03 * ref


def test_fault_tooth_index_checked_per_gear_and_sampling_bounds() -> None:
    """Tooth indices are checked against the faulty gear's own tooth count (0..z − 1);
    n_per_cycle ≥ 4."""
    from geardyn.errors import InputError

    g = seed002_low()  # 42/55
    with pytest.raises(InputError, match="gear a: tooth 42 outside 0..41"):
        mesh_stiffness(g, faults=[Crack(gear="a", tooth=42, depth=1e-3)])
    with pytest.raises(InputError, match="gear b: tooth 55 outside 0..54"):
        mesh_stiffness(g, faults=[Crack(gear="b", tooth=55, depth=1e-3)])
    mesh_stiffness(g, n_per_cycle=4, faults=[Crack(gear="b", tooth=54, depth=1e-3)])
    with pytest.raises(InputError, match="n_per_cycle must be ≥ 4"):
        mesh_stiffness(g, n_per_cycle=3)
