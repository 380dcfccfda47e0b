"""Operating-profile semantics (issue 9, item 6): past the end of a speed or torque profile the
last value is held to the run end, with a warning naming the profile.

Case: the Lin & Parker example stage (z_s = 25, z_r = 95, ring held), the sun under speed
control (k = 1e5 N·m/rad, c = 20 N·m·s/rad) ramped 2000 → 3000 rpm over 4 ms, a carrier load
ramped −50 → −96 N·m over the same 4 ms, run to 12 ms.

Expected after the profiles end (rigid statics and the controller law T = k Δθ + c Δω):
the sun reaction torque is T_s = 96·z_s/(z_s + z_r) = 20 N·m, so the controller holds the sun
at a steady lag Δθ = θ_ref − θ = T_s/k = 2.0e-4 rad behind θ_ref(t) (which keeps growing at
3000 rpm). Tolerances: once settled (2 ms after the end) Δθ stays within ±20 % of T_s/k (mesh
stiffness ripple); the mean speed over the window of length W then differs from 3000 rpm by
at most the change of Δθ over the window divided by W, ≤ 0.4·(T_s/k)/W; each sample is within
0.5 % of 3000 rpm. Before the fix the reference angle stopped growing at the profile end and
the controller stopped the sun.
"""

from __future__ import annotations

import math
import tomllib
import warnings

import numpy as np
import pytest

from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError
from geardyn.models.planetary.build import prepare
from geardyn.models.planetary.dynamics import simulate
from geardyn.operating import ProfileWarning, held_profile, reference_angle_table

from .conftest import EX

RPM = 2 * math.pi / 60
T_END, T_PROFILE, DT = 0.012, 0.004, 2e-5
K_CTRL = 1e5
T_SUN = 96.0 * 25 / (25 + 95)  # N·m, sun reaction of a −96 N·m carrier load, ring held


def _config(t_end: float = T_END) -> object:
    with open(EX / "planetary_lin_parker.toml", "rb") as fh:
        d = tomllib.load(fh)
    s = d["planetary_dynamics"]["simulation"]
    s["t_end_s"] = t_end
    s["initial_speed_rpm"] = {"sun": 2000.0}
    s["speed_controls"][0]["profile_rpm"] = [[0.0, 2000.0], [T_PROFILE, 3000.0]]
    s["speed_controls"][0]["stiffness_nm_per_rad"] = K_CTRL
    s["torques"] = [{"body": "carrier", "profile": [[0.0, -50.0], [T_PROFILE, -96.0]]}]
    return parse_config(d)


def _theta_ref(t: np.ndarray) -> np.ndarray:
    """Reference angle of the ramp then hold, integrated by hand (rad)."""
    ramp = 2000 * RPM * t + 0.5 * (1000 * RPM / T_PROFILE) * t**2
    held = 2500 * RPM * T_PROFILE + 3000 * RPM * (t - T_PROFILE)
    return np.where(t < T_PROFILE, ramp, held)


@pytest.fixture(scope="module")
def run():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        p = prepare(_config())
    ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, T_END, DT)
    return p, ds, [str(w.message) for w in caught if issubclass(w.category, ProfileWarning)]


def test_warnings_name_the_profiles(run):
    _, _, msgs = run
    assert (
        "planetary_dynamics.simulation.speed_controls[0].profile_rpm ends at 0.004 s; "
        "holding 3000 rpm to t_end 0.012 s" in msgs
    )
    assert (
        "planetary_dynamics.simulation.torques[0].profile ends at 0.004 s; "
        "holding -96 N·m to t_end 0.012 s" in msgs
    )


def test_speed_held_after_profile_end(run):
    p, ds, _ = run
    assert ds.attrs["status"] == "ok"
    r = p.model.body("sun").radius
    t = ds.time.values
    win = t >= T_PROFILE + 0.002
    w = ds.v.sel(dof="sun.u").values[win] / r
    width = t[win][-1] - t[win][0]
    assert abs(w.mean() - 3000 * RPM) < 0.4 * (T_SUN / K_CTRL) / width
    assert np.all(np.abs(w / (3000 * RPM) - 1) < 5e-3)


def test_torque_held_after_profile_end(run):
    """The load is held: the force table keeps −96 N·m on the carrier, and the controller
    carries T_s = 20 N·m (a held load of 0 would give no lag)."""
    p, ds, _ = run
    rc = p.model.body("carrier").radius
    j = p.model.dof("carrier.u")
    tq = np.interp([0.005, 0.008, T_END], p.system.force_t, p.system.force[:, j]) * rc
    np.testing.assert_allclose(tq, -96.0, rtol=1e-12)
    r = p.model.body("sun").radius
    t = ds.time.values
    win = t >= T_PROFILE + 0.002
    lag = _theta_ref(t[win]) - ds.q.sel(dof="sun.u").values[win] / r
    assert np.all(np.abs(lag / (T_SUN / K_CTRL) - 1) < 0.2)


@pytest.mark.filterwarnings("ignore:planetary_dynamics.simulation.torques")
def test_cli_t_end_override_extends_the_tables():
    """``prepare(cfg, t_end_s=…)`` (the CLI's --t-end) covers the longer run; the config's
    own t_end is the default."""
    cfg = _config(t_end=T_PROFILE)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ProfileWarning)
        p = prepare(cfg)  # the profiles cover the config's run: no warning
    assert p.t_end_s == T_PROFILE
    with pytest.warns(ProfileWarning, match=r"profile_rpm ends at 0.004 s; holding 3000 rpm "
                      r"to t_end 0.05 s"):
        p = prepare(cfg, t_end_s=0.05)
    assert p.t_end_s == 0.05
    d = p.system.drives  # the speed control is the only drive
    n = d.tlen[0]
    th = np.interp([0.02, 0.05], d.tx[0, :n], d.ty[0, :n])
    np.testing.assert_allclose(th, _theta_ref(np.array([0.02, 0.05])), rtol=1e-9)


@pytest.mark.filterwarnings("ignore::geardyn.operating.ProfileWarning")
def test_bad_profile_names_the_field():
    cfg = _config()
    cfg.planetary_dynamics.simulation.speed_controls[0].profile_rpm = [(0.0, 1.0), (0.0, 2.0)]
    with pytest.raises(ConfigError, match=r"speed_controls\[0\]\.profile_rpm: profile times "
                       r"must increase strictly"):
        prepare(cfg)
    with pytest.raises(ConfigError, match="t_end_s: the run end must be > 0 s"):
        prepare(_config(), t_end_s=0.0)


def test_held_profile_and_reference_angle():
    """A profile starting late holds its first value from 0; the angle table integrates the
    held piecewise-linear speed exactly (θ = ∫ω dt by hand)."""
    with pytest.warns(ProfileWarning) as rec:
        ts, ys = held_profile([[1.0, 10.0], [2.0, 20.0]], 3.0, "x.profile", "rad/s")
    assert [str(r.message) for r in rec] == [
        "x.profile starts at 1 s; holding 10 rad/s from t = 0 s",
        "x.profile ends at 2 s; holding 20 rad/s to t_end 3 s",
    ]
    np.testing.assert_array_equal(ts, [0.0, 1.0, 2.0, 3.0])
    np.testing.assert_array_equal(ys, [10.0, 10.0, 20.0, 20.0])
    tt, th = reference_angle_table(ts, ys)
    np.testing.assert_allclose(np.interp([1.0, 1.5, 2.0, 3.0], tt, th),
                               [10.0, 10 + 0.5 * 12.5, 25.0, 45.0], atol=1e-8)
