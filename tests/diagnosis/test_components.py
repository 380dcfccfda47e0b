"""Machine components from the kinematics: signed ratios, own angles and mesh/bearing orders
against closed forms (Willis for a fixed-ring planetary stage, tooth-count ratios for parallel
stages, Harris' BPFO for a fixed outer ring)."""

from __future__ import annotations

from pathlib import Path

import pytest

import geardyn
from geardyn.diagnosis.components import link_ratios, machine_components
from geardyn.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_seed004_planetary_own_angles_from_willis():
    """Fixed ring, Z_s = 19, Z_p = 32, Z_r = 83 (seed 004 Table 6-2): carrier ω_c/ω_s =
    Z_s/(Z_s+Z_r) = 19/102; sun relative to carrier 83/102; planet relative to carrier
    −(Z_s/Z_p)·83/102; ring relative to carrier −19/102 (|.| = carrier angle)."""
    comps = machine_components(geardyn.load_config(EXAMPLES / "planetary_reclaimer.toml"), "sun")
    assert comps.ratios["carrier"] == pytest.approx(19 / 102, rel=1e-12)
    sun = comps["planetary.sun"]
    assert (sun.kind, sun.ratio, sun.mesh_orders) == ("sun", pytest.approx(83 / 102), (19,))
    ring = comps["planetary.ring"]
    assert (ring.kind, ring.ratio, ring.mesh_orders) == ("ring", pytest.approx(-19 / 102), (83,))
    planets = comps.of_kind("planet")
    assert [p.planet for p in planets] == [0, 1, 2]
    for p in planets:
        assert p.ratio == pytest.approx(-19 / 32 * 83 / 102, rel=1e-12)
        assert p.mesh_orders == (32,)
    (st,) = comps.planetary
    assert (st.n_planets, st.sun_teeth, st.ring_teeth, st.planet_sun_teeth) == (3, 19, 83, 32)
    assert st.ring_fixed
    # planets are not shafts; the carrier (no fixed-axis wheel) is, with no mesh orders
    assert {s.name for s in comps.shafts} == {"sun", "carrier"}
    assert comps["carrier"].mesh_orders == ()


def test_seed002_counter_rotating_shaft_has_a_negative_ratio_and_all_its_meshes():
    """Seed 002 two-stage transmission: ω_int/ω_in = −31/53 (external pair reverses),
    ω_out/ω_in = (31/53)(42/55); the intermediate shaft carries the 53- and 42-tooth wheels, so
    its TSA must remove both meshes and each wheel's sidebands are ambiguous near the other's."""
    comps = machine_components(geardyn.load_config(EXAMPLES / "seed002_transmission.toml"), "input")
    inter = comps["intermediate"]
    assert inter.ratio == pytest.approx(-31 / 53, rel=1e-12)
    assert inter.abs_ratio == pytest.approx(31 / 53, rel=1e-12)
    assert sorted(inter.mesh_orders) == [42, 53]
    assert comps["output"].ratio == pytest.approx(31 / 53 * 42 / 55, rel=1e-12)
    w42 = comps["intermediate/z42"]
    assert (w42.kind, w42.teeth, w42.other_orders, w42.others) == (
        "wheel",
        42,
        (53,),
        ("intermediate/z53",),
    )
    assert comps["input/z31"].other_orders == ()


def test_bearing_orders_from_harris_formulas():
    """Deep-groove ball bearing of seed 002 Table 3 (11 balls, d = 12.7 mm, D = 80 mm, α = 0),
    outer ring fixed: BPFO = (N/2)(1 − d/D)·f_r = 4.626875 orders of its own shaft, FTF =
    ½(1 − d/D) = 0.4206; on the output shaft, times its ratio (31/53)(42/55)."""
    comps = machine_components(geardyn.load_config(EXAMPLES / "seed002_transmission.toml"), "input")
    b = comps["input ball"]
    assert b.kind == "bearing" and b.link == "input"
    assert b.fault_orders["BPFO"] == pytest.approx(5.5 * (1 - 12.7 / 80), rel=1e-12)
    assert b.fault_orders["FTF"] == pytest.approx(0.5 * (1 - 12.7 / 80), rel=1e-12)
    out = comps["output ball"]
    assert out.fault_orders["BPFO"] == pytest.approx(
        5.5 * (1 - 12.7 / 80) * 31 / 53 * 42 / 55, rel=1e-12
    )
    table = comps.table()
    assert {"component", "kind", "ratio", "mesh_orders", "bpfo_order"} <= set(table.columns)
    assert len(table) == len(comps.items)


def test_two_dof_needs_input_speeds():
    """Car differential (seed 000 §3.1, 2 DOF): ratios to one wheel are not fixed, so the
    error names the DOF and the candidate links (a kinematic analysis carries no operating
    point; a config gives its input_speeds_rpm); with both wheel speeds the ratio of the
    right wheel to the left is their quotient (286.5/248.3)."""
    cfg = geardyn.load_config(EXAMPLES / "car_differential.toml")
    with pytest.raises(InputError, match="2 degrees of freedom.*input_speeds.*right_wheel"):
        machine_components(geardyn.analyze_kinematics(cfg), "left_wheel")
    speeds = {"left_wheel": 248.3, "right_wheel": 286.5}
    r = link_ratios(geardyn.analyze_kinematics(cfg), "left_wheel", speeds)
    assert r["right_wheel"] == pytest.approx(286.5 / 248.3, rel=1e-12)
    comps = machine_components(cfg, "left_wheel", speeds)
    assert comps["right_wheel"].ratio == pytest.approx(286.5 / 248.3, rel=1e-12)


def test_bad_reference_is_named():
    cfg = geardyn.load_config(EXAMPLES / "seed002_transmission.toml")
    with pytest.raises(InputError, match="reference: unknown link 'nope'"):
        machine_components(cfg, "nope")
    with pytest.raises(InputError, match="reference: 'housing' is the frame"):
        machine_components(cfg, "housing")
    with pytest.raises(InputError, match="cfg: expected a Mechanism"):
        machine_components(42, "input")
    with pytest.raises(InputError, match="component: unknown name"):
        machine_components(cfg, "input")["nope"]


def test_two_dof_components_take_the_configs_operating_point(examples_dir):
    """A 2-DOF mechanism (car differential, Penaud et al. 2012 eq 8: wheels at 26 and 30 rad/s)
    given as a config: its input_speeds_rpm set the ratios (the diagnosis of the
    `differential` template). Reference: the cage of an open differential turns at the mean
    of the side gears, (26 + 30) / 2 = 28 rad/s, so left/cage = 26/28, right/cage = 30/28."""
    from geardyn.config import load_config
    from geardyn.diagnosis.components import machine_components

    cfg = load_config(examples_dir / "car_differential_dynamics.toml")
    comps = machine_components(cfg, "cage")
    assert comps.ratios["left_wheel"] == pytest.approx(26 / 28, rel=1e-6)
    assert comps.ratios["right_wheel"] == pytest.approx(30 / 28, rel=1e-6)
    # crown pair 13/65, signed as in Penaud et al. 2012 Table 1 (pinion at −2.5 × each wheel)
    assert comps.ratios["drive_pinion"] == pytest.approx(-65 / 13, rel=1e-9)
    assert comps.input_speeds == pytest.approx(cfg.input_speeds_rpm)
