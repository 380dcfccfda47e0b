"""PE mesh stiffness: seed 002 eqs 6-7 against independent evaluations, and invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from geardyn.errors import InputError
from geardyn.gears.contact import hertz_compliance
from geardyn.gears.faults import Crack, Spall
from geardyn.gears.fillet_foundation import fillet_foundation_compliance, sainsot_coefficient
from geardyn.gears.geometry import GearBlank, mesh_geometry
from geardyn.gears.pe_stiffness import mesh_stiffness, tooth_compliance

from .seed002 import A20, STEEL, seed002_high, seed002_low


# ---- Sainsot coefficients (seed 002 Table 5, eq 3.2) ----------------------------------------
def test_sainsot_coefficients_by_hand():
    # θ_f = 0.2 rad, h_fi = 1.5, terms A/θ² + B h² + C h/θ + D/θ + E h + F from Table 5:
    # L* = -5.574e-5/0.04 - 1.9986e-3*2.25 - 2.3015e-4*7.5 + 4.7702e-3*5 + 0.0271*1.5 + 6.8045
    #    = -0.0013935 - 0.00449685 - 0.001726125 + 0.023851 + 0.04065 + 6.8045 = 6.861384525
    assert sainsot_coefficient("L", 0.2, 1.5) == pytest.approx(6.861384525, abs=1e-9)
    # M* = 60.111e-5/0.04 + 28.1e-3*2.25 - 83.431e-4*7.5 - 9.9256e-3*5 + 0.1624*1.5 + 0.9086
    #    = 0.015027750 + 0.063225 - 0.06257325 - 0.049628 + 0.2436 + 0.9086 = 1.1182515
    assert sainsot_coefficient("M", 0.2, 1.5) == pytest.approx(1.1182515, abs=1e-9)
    # P* = -50.952e-5/0.04 + 185.5e-3*2.25 + 0.0538e-4*7.5 + 53.3e-3*5 + 0.2895*1.5 + 0.9236
    #    = -0.012738 + 0.417375 + 0.00004035 + 0.2665 + 0.43425 + 0.9236 = 2.02902735
    assert sainsot_coefficient("P", 0.2, 1.5) == pytest.approx(2.02902735, abs=1e-9)
    # Q* = -6.2042e-5/0.04 + 9.0889e-3*2.25 - 4.0964e-4*7.5 + 7.8297e-3*5 - 0.1472*1.5 + 0.6904
    #    = -0.00155105 + 0.020450025 - 0.0030723 + 0.0391485 - 0.2208 + 0.6904 = 0.524575175
    assert sainsot_coefficient("Q", 0.2, 1.5) == pytest.approx(0.524575175, abs=1e-9)


def test_fillet_foundation_formula():
    # eq 7 at β = 0: 1/K_f = (L* (u/S)² + M* u/S + P*)/(E δz)
    lc, mc, pc = (sainsot_coefficient(x, 0.2, 1.5) for x in "LMP")
    val = fillet_foundation_compliance(
        np.array([0.0]), np.array([0.004]), 0.005, 0.2, 1.5, 2e11, 0.01
    )
    assert val[0] == pytest.approx((lc * 0.64 + mc * 0.8 + pc) / (2e11 * 0.01), rel=1e-12, abs=0)


# ---- eq 6 against Tian's closed-form integrals (root circle = base circle) -----------------
def _tian(alpha1: float, alpha2: float, e: float, nu: float) -> tuple[float, float, float]:
    def den(a):
        return math.sin(a) + (alpha2 - a) * math.cos(a)

    def fb(a):
        num = 3 * (1 + math.cos(alpha1) * ((alpha2 - a) * math.sin(a) - math.cos(a))) ** 2
        return num * (alpha2 - a) * math.cos(a) / (2 * e * den(a) ** 3)

    def fs(a):
        return 1.2 * (1 + nu) * (alpha2 - a) * math.cos(a) * math.cos(alpha1) ** 2 / (e * den(a))

    def fa(a):
        return (alpha2 - a) * math.cos(a) * math.sin(alpha1) ** 2 / (2 * e * den(a))

    return tuple(quad(f, -alpha1, alpha2, limit=200)[0] for f in (fb, fs, fa))


def test_eq6_matches_tian_closed_form():
    rb = 0.04 * math.cos(A20)
    g = mesh_geometry(
        GearBlank(40, root_radius=rb, material=STEEL), GearBlank(40), 0.002, A20, 0.02
    )
    a2 = g.half_angle_base[0]
    for r in np.linspace(rb * 1.02, g.tip_radius[0] * 0.999, 5):
        c = tooth_compliance(g, 0, np.array([r]))
        alpha1 = math.tan(math.acos(rb / r)) - a2
        kb, ks, ka = _tian(alpha1, a2, STEEL.youngs_modulus, STEEL.poisson_ratio)
        assert c.bending[0] == pytest.approx(kb, rel=1e-5, abs=0)
        assert c.shear[0] == pytest.approx(ks, rel=1e-5, abs=0)
        assert c.axial[0] == pytest.approx(ka, rel=1e-5, abs=0)


def test_hertz_constant_form():
    # k_h = π E L / (4 (1 − ν²)) for equal materials
    assert 1 / hertz_compliance(2e11, 0.3, 2e11, 0.3, 0.01) == pytest.approx(
        math.pi * 2e11 * 0.01 / (4 * (1 - 0.09)), rel=1e-12
    )


def test_compliance_grows_towards_tip():
    g = seed002_low()
    r = np.linspace(g.contact_radii(g.u_start)[0], g.tip_radius[0], 20)
    c = tooth_compliance(g, 0, r)
    assert np.all(np.diff(c.bending) > 0)
    assert np.all(c.fillet > 0) and np.all(c.shear > 0)


# ---- mesh stiffness invariants -------------------------------------------------------------
def test_periodic_over_mesh_cycle():
    g = seed002_low()
    t = mesh_stiffness(g, n_per_cycle=50, n_cycles=3, n_slices=1)
    assert np.allclose(t.total[:50], t.total[50:100], rtol=1e-12)
    # faulty tables are periodic over the hunting period (lcm(42, 55) cycles), not one cycle
    tf = mesh_stiffness(g, n_per_cycle=8, n_cycles=None, faults=[Crack("b", 3, 0.0005)])
    assert tf.total.size == 8 * math.lcm(42, 55)
    th = mesh_stiffness(g, n_per_cycle=8, n_cycles=None)
    loss = th.total - tf.total > 1e-9 * th.total
    # the cracked wheel tooth meets the pinion once per wheel revolution: lcm/55 = 42 windows
    starts = np.count_nonzero(loss & ~np.roll(loss, 1))
    assert starts == math.lcm(42, 55) // 55


def test_double_contact_stiffer_than_single():
    g = seed002_low()
    t = mesh_stiffness(g, n_per_cycle=200)
    npairs = (t.pair_stiffness > 0).sum(axis=1)
    assert set(np.unique(npairs)) == {1, 2}
    assert t.total[npairs == 2].min() > t.total[npairs == 1].max()
    # time fraction in double contact = ε_α − 1
    assert np.mean(npairs == 2) == pytest.approx(g.contact_ratio - 1, abs=0.01)


def test_internal_mesh_has_two_to_three_pairs():
    g = mesh_geometry(
        GearBlank(32, form_radius=0.0),
        GearBlank(83, internal=True, addendum_coef=1.25),
        0.016,
        A20,
        0.245,
    )
    t = mesh_stiffness(g, n_per_cycle=200)
    npairs = (t.pair_stiffness > 0).sum(axis=1)
    assert set(np.unique(npairs)) == {2, 3}
    assert t.total[npairs == 3].min() > t.total[npairs == 2].max()


def test_crack_depth_monotone_loss():
    g = seed002_low()
    means = []
    for q in (0.0, 0.3e-3, 0.6e-3, 1.0e-3, 1.5e-3):
        faults = [Crack("b", 0, q)] if q else []
        t = mesh_stiffness(g, n_per_cycle=32, n_cycles=3, faults=faults, n_slices=4)
        means.append(t.total.min())
    assert np.all(np.diff(means) < 0)


def test_crack_law_partial_width_between():
    g = seed002_low()
    kw = dict(n_per_cycle=32, n_cycles=3, n_slices=10)
    full = mesh_stiffness(g, faults=[Crack("b", 0, 1e-3)], **kw).total.min()
    lin = mesh_stiffness(g, faults=[Crack("b", 0, 1e-3, law="linear")], **kw).total.min()
    healthy = mesh_stiffness(g, **kw).total.min()
    assert full < lin < healthy


def test_spall_acts_only_while_in_contact():
    g = seed002_low()
    sp = Spall(
        "b",
        1,
        radius=0.0825,
        radial_width=0.0029,
        depth=1e-4,
        axial_position=0.0125,
        axial_length=0.0125,
    )
    kw = dict(n_per_cycle=100, n_cycles=4, n_slices=20)
    h = mesh_stiffness(g, **kw)
    f = mesh_stiffness(g, faults=[sp], **kw)
    diff = h.total - f.total
    assert diff.max() > 0
    # expected window: pair with gear-b tooth 1 whose contact radius on b is in the band
    on = np.zeros_like(diff, dtype=bool)
    k_spalled_pair = np.zeros_like(diff)
    for p in range(h.pair_stiffness.shape[1]):
        u = h.contact[:, p]
        rb_ = g.contact_radii(np.nan_to_num(u))[1]
        hit = (h.tooth_b[:, p] == 1) & np.isfinite(u) & (np.abs(rb_ - 0.0825) <= 0.00145)
        on |= hit
        k_spalled_pair += np.where(hit, h.pair_stiffness[:, p], 0.0)
    assert on.any() and not on.all()
    assert np.all(np.abs(diff[~on]) <= 1e-12 * h.total.max())
    # the spall covers half the face (10 of 20 slices): the spalled pair loses half its stiffness
    assert np.allclose(diff[on], 0.5 * k_spalled_pair[on], rtol=1e-9)


def test_helical_smoother_than_spur():
    hel_g = seed002_high(20.0)
    # spur equivalent: same transverse geometry (module m_t, same radii), straight teeth
    spur_g = mesh_geometry(
        hel_g.a,
        hel_g.b,
        hel_g.transverse_module,
        hel_g.transverse_pressure_angle,
        0.025,
        label="spur-equivalent",
    )
    assert spur_g.contact_ratio == pytest.approx(hel_g.contact_ratio, rel=1e-9)
    hel = mesh_stiffness(hel_g, n_per_cycle=128, n_slices=40).total
    spur = mesh_stiffness(spur_g, n_per_cycle=128).total
    fl_h = np.ptp(hel) / hel.mean()
    fl_s = np.ptp(spur) / spur.mean()
    assert fl_h < 0.5 * fl_s
    # and smoother: smaller mean absolute step between samples
    step_h = np.mean(np.abs(np.diff(hel))) / hel.mean()
    step_s = np.mean(np.abs(np.diff(spur))) / spur.mean()
    assert step_h < step_s


def test_more_slices_converge():
    g = seed002_high()
    k20 = mesh_stiffness(g, n_per_cycle=64, n_slices=20).total.mean()
    k80 = mesh_stiffness(g, n_per_cycle=64, n_slices=80).total.mean()
    assert k20 == pytest.approx(k80, rel=0.01)


def test_hunting_table_fast():
    import time

    g = mesh_geometry(GearBlank(50), GearBlank(53), 0.003, A20, 0.025)
    t0 = time.perf_counter()
    t = mesh_stiffness(g, n_per_cycle=32, n_cycles=None, faults=[Crack("a", 7, 5e-4)], n_slices=8)
    assert time.perf_counter() - t0 < 2.0  # benchmark shows well under 1 s
    assert t.total.size == 32 * 50 * 53


def test_xarray_output():
    t = mesh_stiffness(seed002_low(), n_per_cycle=16, n_cycles=2)
    ds = t.to_xarray()
    assert set(ds.dims) == {"angle", "pair"}
    assert np.allclose(ds["total"].values, ds["pair_stiffness"].sum("pair").values)
    assert ds["angle"].values[16] == pytest.approx(2 * math.pi / 42)


def test_bad_inputs():
    g = seed002_low()
    with pytest.raises(InputError, match="tooth 60"):
        mesh_stiffness(g, faults=[Crack("b", 60, 1e-3)])
    with pytest.raises(InputError, match="cuts through"):
        mesh_stiffness(g, faults=[Crack("b", 0, 0.01)], n_cycles=2)
