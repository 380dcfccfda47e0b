"""Involute geometry against seed 004 Table 4-2 and seed 002 Table 2; checks with clear errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.errors import ConfigError
from geardyn.gears.geometry import GearBlank, mesh_geometry

A20 = math.radians(20.0)
M = 0.016  # seed 004 module
MM = 1e-3
TOL_MM = 1e-4 * MM  # Table 4-2 prints 4 decimals (mm)


@pytest.fixture(scope="module")
def sun():
    return mesh_geometry(GearBlank(19), GearBlank(32), M, A20, 0.245, label="sun")


@pytest.fixture(scope="module")
def ring():
    # thesis code: ring "tip" R_ra = 644 mm (h_a* = 1.25), involute down to the planet base circle
    return mesh_geometry(
        GearBlank(32, form_radius=0.0),
        GearBlank(83, internal=True, addendum_coef=1.25),
        M,
        A20,
        0.245,
        label="ring",
    )


def test_table_4_2_radii(sun, ring):
    assert sun.base_radius[0] == pytest.approx(142.8333 * MM, abs=TOL_MM)
    assert sun.base_radius[1] == pytest.approx(240.5613 * MM, abs=TOL_MM)
    assert ring.base_radius[1] == pytest.approx(623.9559 * MM, abs=TOL_MM)
    assert sun.tip_radius == pytest.approx((168 * MM, 272 * MM))
    assert sun.root_radius == pytest.approx((132 * MM, 236 * MM))
    assert sun.base_pitch == pytest.approx(47.2341 * MM, abs=TOL_MM)
    assert ring.tip_radius[1] == pytest.approx(644 * MM)


def test_table_4_2_sun_mesh_lengths(sun):
    # B_sE_s (path), B_sP_s (start to pitch point), B_sC_s = B_sE_s − p_b
    assert sun.path_length == pytest.approx(75.8435 * MM, abs=TOL_MM)
    assert -sun.u_start == pytest.approx(39.3848 * MM, abs=TOL_MM)
    assert sun.path_length - sun.base_pitch == pytest.approx(28.6094 * MM, abs=TOL_MM)
    # M_sE_s = √(R_sa² − R_sb²) = u_end + M_sP_s
    m_sp = sun.base_radius[0] * math.tan(A20)
    assert m_sp == pytest.approx(51.9871 * MM, abs=TOL_MM)
    assert sun.u_end + m_sp == pytest.approx(88.4458 * MM, abs=TOL_MM)


def test_table_4_2_ring_mesh_lengths(ring):
    assert ring.path_length == pytest.approx(107.0652 * MM, abs=TOL_MM)
    assert -ring.u_start == pytest.approx(67.6804 * MM, abs=TOL_MM)
    # the thesis prints B_rC_r = 107.0180 (typo); B_rE_r − p_b = 59.8311 (notes §4.1)
    assert ring.path_length - ring.base_pitch == pytest.approx(59.8311 * MM, abs=TOL_MM)


def test_contact_ratios_seed004(sun, ring):
    assert sun.contact_ratio == pytest.approx(1.60569, abs=1e-5)
    assert ring.contact_ratio == pytest.approx(2.26669, abs=1e-5)


def test_standard_ring_tip_gives_lower_ratio():
    g = mesh_geometry(GearBlank(32, form_radius=0.0), GearBlank(83, internal=True), M, A20, 0.245)
    assert g.tip_radius[1] == pytest.approx(0.648)
    assert 1.0 < g.contact_ratio < 2.26669


def test_seed002_table2_tip_radii():
    # derived from h_a* = 1 they reproduce Table 2's addendum radii
    low = mesh_geometry(GearBlank(42), GearBlank(55), 0.003, A20, 0.025)
    assert low.tip_radius == pytest.approx((66 * MM, 85.5 * MM), abs=1e-9)
    high = mesh_geometry(GearBlank(31), GearBlank(53), 0.003, A20, 0.025, math.radians(20))
    assert high.tip_radius[0] == pytest.approx(52.5 * MM, abs=0.02 * MM)
    assert high.tip_radius[1] == pytest.approx(87.6 * MM, abs=0.01 * MM)
    # helical: α_t = atan(tan 20°/cos 20°) = 21.1728°, ε_β = b tan β_b / p_bt
    assert math.degrees(high.transverse_pressure_angle) == pytest.approx(21.1728, abs=1e-4)
    eps_b = 0.025 * math.sin(math.radians(20)) / (math.pi * 0.003)
    assert high.overlap_ratio == pytest.approx(eps_b, rel=1e-9)


def test_tooth_thickness_at_pitch():
    g = mesh_geometry(GearBlank(30), GearBlank(40), 0.004, A20, 0.02)
    assert float(g.tooth_thickness(0, g.pitch_radius[0])) == pytest.approx(
        math.pi * 0.004 / 2, rel=1e-9
    )
    x = 0.3
    gs = mesh_geometry(GearBlank(30, profile_shift=x), GearBlank(40), 0.004, A20, 0.02)
    s = 0.004 * (math.pi / 2 + 2 * x * math.tan(A20))
    assert float(gs.tooth_thickness(0, gs.pitch_radius[0])) == pytest.approx(s, rel=1e-9)
    # internal: tooth + space = pitch at any radius
    r = mesh_geometry(
        GearBlank(20), GearBlank(70, internal=True, addendum_coef=0.8), 0.004, A20, 0.02
    )
    rr = r.pitch_radius[1]
    assert float(r.tooth_thickness(1, rr)) == pytest.approx(math.pi * 0.004 / 2, rel=1e-9)


def test_profile_shift_centre_distance():
    # inv α_w = inv α + 2 tan α (x1 + x2)/(z1 + z2); a_w = a cos α / cos α_w
    g = mesh_geometry(
        GearBlank(12, profile_shift=0.4), GearBlank(30, profile_shift=0.2), 0.005, A20, 0.03
    )
    aw = g.working_pressure_angle
    assert math.tan(aw) - aw == pytest.approx(
        math.tan(A20) - A20 + 2 * math.tan(A20) * 0.6 / 42, rel=1e-12
    )
    assert g.centre_distance == pytest.approx(0.005 * 42 / 2 * math.cos(A20) / math.cos(aw))


def test_path_positions_roll_angles(sun):
    u = np.array([sun.u_start, sun.u_end])
    ra, rb = sun.contact_radii(u)
    assert rb[0] == pytest.approx(sun.tip_radius[1])
    assert ra[1] == pytest.approx(sun.tip_radius[0])
    ta, tb = sun.roll_angles(u)
    # roll angles increase on a and decrease on b by path/r_b
    assert ta[1] - ta[0] == pytest.approx(sun.path_length / sun.base_radius[0])
    assert tb[0] - tb[1] == pytest.approx(sun.path_length / sun.base_radius[1])


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        (
            dict(a=GearBlank(40, addendum_coef=0.4), b=GearBlank(40, addendum_coef=0.4)),
            "transverse contact ratio",
        ),
        (dict(a=GearBlank(9), b=GearBlank(40)), "undercut"),
        (dict(a=GearBlank(12, profile_shift=1.2), b=GearBlank(40)), "tip is"),
        (dict(a=GearBlank(40, internal=True), b=GearBlank(20)), "must be external"),
        (dict(a=GearBlank(20), b=GearBlank(24, internal=True)), "at least 6 more teeth"),
        (dict(a=GearBlank(32), b=GearBlank(83, internal=True, addendum_coef=1.25)), "interference"),
        (dict(a=GearBlank(20), b=GearBlank(60, internal=True, tip_radius=0.05)), "base circle"),
    ],
)
def test_checks_name_the_rule(kwargs, fragment):
    m = 0.016 if kwargs["b"].teeth == 83 else 0.002
    with pytest.raises(ConfigError) as exc:
        mesh_geometry(kwargs["a"], kwargs["b"], m, A20, 0.02, label="low")
    assert fragment in str(exc.value)
    assert "gear pair 'low'" in str(exc.value)


def test_contact_ratio_message_value():
    with pytest.raises(ConfigError, match=r"transverse contact ratio 0\.\d+ < 1"):
        mesh_geometry(
            GearBlank(40, addendum_coef=0.4),
            GearBlank(40, addendum_coef=0.4),
            0.002,
            A20,
            0.02,
            label="low",
        )


def test_base_pitch_mismatch():
    with pytest.raises(ConfigError, match="normal base pitches differ"):
        mesh_geometry(GearBlank(20), GearBlank(30), 0.002, A20, 0.02, module_b=0.0025)
    # same base pitch with another tool: allowed
    ab = math.acos(0.002 * math.cos(A20) / 0.0021)
    mesh_geometry(
        GearBlank(20), GearBlank(30), 0.002, A20, 0.02, module_b=0.0021, pressure_angle_b=ab
    )


def test_tip_round_shortens_path():
    from geardyn.gears.geometry import active_tip_radius

    # α_a = 30°: drop = ρ cos 30°/tan 60° = ρ/2 exactly
    assert active_tip_radius(0.05, 0.05 * math.cos(math.radians(30)), 0.5e-3) == pytest.approx(
        0.05 - 0.25e-3, rel=1e-12
    )
    assert active_tip_radius(0.6, 0.5, 0.0) == 0.6
    sharp = mesh_geometry(GearBlank(42), GearBlank(55), 0.003, A20, 0.025)
    rounded = mesh_geometry(
        GearBlank(42, tip_round=0.5e-3), GearBlank(55, tip_round=0.5e-3), 0.003, A20, 0.025
    )
    assert rounded.contact_ratio < sharp.contact_ratio
    assert rounded.tip_radius == sharp.tip_radius  # nominal tips unchanged
