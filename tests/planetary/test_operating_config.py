"""Operating conditions (seed 004 §6, seed 003 eq 1.18) and config rules."""

from __future__ import annotations

import copy
import math
import tomllib

import numpy as np
import pytest

from geardyn.config.loader import load_config, parse_config
from geardyn.errors import ConfigError
from geardyn.models.planetary.build import prepare
from geardyn.models.planetary.dynamics import simulate
from geardyn.operating import (
    BucketWheelSchedule,
    KlossMotor,
    PiecewiseMotor,
    coupling_slip,
    hollow_cylinder,
    run_up,
)

from .conftest import EX


def test_seed004_motor_numbers():
    """Notes §4.1: T_fl 4342.4, T_su 9987.6, T_max 11290 N·m, n_sync 1000, n_bd 870 rpm."""
    m = PiecewiseMotor()
    assert m.full_load_torque == pytest.approx(4342.42, abs=0.01)
    assert m.sync_rpm == 1000.0 and m.breakdown_rpm == pytest.approx(870.0)
    t = m.torque([0.0, 870.0, 950.0, 1000.0, 1100.0])
    np.testing.assert_allclose(t, [9987.56, 11290.28, 4342.42, 0.0, 0.0], atol=0.01)
    # fluid coupling slip at T_fl and 950 rpm with q_cc = 15: 2.93 % (notes §2.9)
    assert coupling_slip(15.0, m.full_load_torque, 950 * 2 * math.pi / 60) == pytest.approx(
        0.0293, abs=5e-5)


def test_kloss_motor_breakdown():
    """Seed 003 eq 1.18 at s = s_b gives T_b; zero speed gives the starting torque."""
    m = KlossMotor(breakdown_torque=200.0, breakdown_slip=0.2, a=1.0, b=0.5, sync_rpm=1500)
    assert float(m.torque(1500 * (1 - 0.2))) == pytest.approx(200.0)
    s = 1.0
    assert float(m.torque(0.0)) == pytest.approx(200 / (1 + (0.2 - s) ** 2 * (1 / s - 0.5 * s**2)))


def test_hollow_cylinders_and_schedule():
    """Seed 004 eqs 6.8-6.9 (Table 6-4: sun 98.9691 kg, 1.4760 kg·m²; planet 284.2189, 11.9417)
    and the schedule points of notes §4.1 (P44 = 1.2818 m of u_c at r_c = 0.408 m, ...)."""
    m, j = hollow_cylinder(0.245, 7850, 0.304, 0.164)
    assert (m, j) == (pytest.approx(98.9691, abs=1e-4), pytest.approx(1.4760, abs=1e-4))
    m, j = hollow_cylinder(0.245, 7850, 0.512, 0.272)
    assert (m, j) == (pytest.approx(284.2189, abs=1e-4), pytest.approx(11.9417, abs=1e-4))
    p = BucketWheelSchedule().points()
    for k, v in {"P44": 1.2818, "P45": 2.3499, "P46": 5.1698, "P47": 6.2379, "P48": 0.21363,
                 "P49": 3.6317, "P50": 4.1444, "P94": 0.05341}.items():
        assert p[k] * 0.408 == pytest.approx(v, abs=1e-4), k
    s = BucketWheelSchedule()
    assert float(s.ore(0.5)) == 0.0 and float(s.ore(p["P45"])) == pytest.approx(3.1)
    assert float(s.ore(p["P45"] + p["P94"])) == pytest.approx(3.1 - 0.8)
    assert float(s.load_factor(p["P49"] + 0.01)) > 10


def test_run_up_profile():
    t = np.linspace(0, 2, 5)
    np.testing.assert_allclose(run_up(t, 0.0, 100.0, 0.5, 1.5), [0, 0, 50, 100, 100])


@pytest.mark.parametrize("name", sorted(p.name for p in EX.glob("planetary_*.toml")))
def test_examples_load_and_run(name):
    cfg = load_config(EX / name)
    p = prepare(cfg)
    sim = cfg.planetary_dynamics.simulation
    t_end = min(sim.t_end_s, 200 * sim.dt_s)
    ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, t_end, sim.dt_s)
    assert ds.attrs["status"] == "ok"
    assert np.all(np.isfinite(ds.q.values))
    assert any(str(d).endswith("sun.u") for d in ds.dof.values)
    assert ds.q.attrs["units"].startswith("m") and ds.time.attrs["units"] == "s"


def _raw(name):
    with open(EX / name, "rb") as fh:
        return tomllib.load(fh)


def test_planets_that_do_not_fit_rejected():
    d = copy.deepcopy(_raw("planetary_lin_parker.toml"))
    d["planetary_dynamics"]["stages"][0]["planet"]["tip_radius_m"] = 0.05
    with pytest.raises(ConfigError, match="planets do not fit"):
        parse_config(d)


def test_negative_stiffness_rejected():
    d = copy.deepcopy(_raw("planetary_lin_parker.toml"))
    d["planetary_dynamics"]["stages"][0]["planet_bearing_n_per_m"] = -1e8
    with pytest.raises(ConfigError, match="planet_bearing_n_per_m.*greater than 0"):
        parse_config(d)
    d = copy.deepcopy(_raw("planetary_lin_parker.toml"))
    d["planetary_dynamics"]["stages"][0]["sun"]["bearing_n_per_m"] = -5.0
    with pytest.raises(ConfigError, match="bearing_n_per_m.*greater than or equal to 0"):
        parse_config(d)


def test_unknown_body_and_stage_rejected():
    d = copy.deepcopy(_raw("planetary_bench_36dof.toml"))
    d["planetary_dynamics"]["shafts"][0]["b"] = "test.moon"
    with pytest.raises(ConfigError, match=r"shafts\[0\] 'sun_shaft'.b: unknown body 'test.moon'"):
        parse_config(d)
    d = copy.deepcopy(_raw("planetary_lin_parker.toml"))
    d["planetary_dynamics"]["stages"][0]["stage"] = "nope"
    with pytest.raises(ConfigError, match="unknown planetary stage 'nope'"):
        parse_config(d)
    d = copy.deepcopy(_raw("planetary_lin_parker.toml"))
    d["planetary_dynamics"]["simulation"]["torques"][0]["body"] = "sun2"
    with pytest.raises(ConfigError, match="simulation.torques: unknown body 'sun2'"):
        parse_config(d)


def test_inconsistent_geometry_rejected():
    """r_c cos α_s = r_bs + r_bp is required for a strain-free rigid rotation."""
    d = copy.deepcopy(_raw("planetary_lin_parker.toml"))
    d["planetary_dynamics"]["stages"][0]["pressure_angle_sun_deg"] = 20.0
    with pytest.raises(ConfigError, match="pressure_angle_sun_deg: inconsistent with the radii"):
        parse_config(d)


@pytest.mark.parametrize(("name", "rpm_end"), [("planetary_bench_12dof.toml", 1498.5),
                                               ("planetary_bench_12dof_rundown.toml", 1000.0)])
def test_bench_run_up_and_run_down_follow_the_profile(name, rpm_end):
    """Seed 003 ch. 4 run-up/run-down: the speed-controlled motor follows the ramp and the
    carriers turn at z_s/(z_s + z_r) = 16/81 of it (Willis, ring held)."""
    cfg = load_config(EX / name)
    p = prepare(cfg)
    sim = cfg.planetary_dynamics.simulation
    ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, sim.t_end_s, sim.dt_s)
    last = ds.isel(time=slice(-200, None))
    w_s = float(last.v.sel(dof="reaction.sun.u").mean()) / p.model.body("reaction.sun").radius
    w_c = float(last.v.sel(dof="test.carrier.u").mean()) / p.model.body("test.carrier").radius
    prof = np.array(sim.speed_controls[0].profile_rpm)
    ref = np.interp(last.time.values, prof[:, 0], prof[:, 1]).mean()
    assert w_s * 60 / (2 * math.pi) == pytest.approx(ref, rel=0.01)
    assert abs(ref - rpm_end) < 0.05 * rpm_end
    assert w_c / w_s == pytest.approx(16 / 81, rel=0.02)
