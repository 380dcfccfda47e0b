"""Baseline ensemble (issue 18): draws, determinism, perturbed configs, re-measurement.

References: the draws are U(1 − t, 1 + t) by construction (mean 1, std t/√3); their sample
statistics are compared with the sampling error of a uniform (standard error of the mean
σ/√N, of the sample variance σ²·√(0.8/N) from the fourth moment 9σ⁴/5), at 4 standard errors.
The re-measured channels are compared with an independent path (a full ``run_simulation`` of
the member's config), bit for bit.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from geardyn.config.diagnosis import DiagnosisSpec
from geardyn.config.loader import load_config, parse_config
from geardyn.diagnosis.ensemble import member_configs, simulate_baseline
from geardyn.diagnosis.faults import healthy_variant
from geardyn.errors import ConfigError
from geardyn.run import run_simulation

EX = Path(__file__).resolve().parents[2] / "examples"
PLANETARY = EX / "seed004_diagnose_sun_crack.toml"
FE = EX / "seed002_diagnose_spall.toml"


@pytest.fixture(scope="module")
def healthy():
    return healthy_variant(load_config(PLANETARY))


def _spec(seeds=(0, 1, 2), **ens) -> DiagnosisSpec:
    return DiagnosisSpec(baseline_seeds=list(seeds), ensemble=ens)


def test_member_seeds_follow_members_unless_given():
    assert DiagnosisSpec().baseline_seeds == list(range(DiagnosisSpec().ensemble.members))
    assert DiagnosisSpec(ensemble={"members": 4}).baseline_seeds == [0, 1, 2, 3]
    given = DiagnosisSpec(baseline_seeds=[5, 7, 9])
    assert given.ensemble.members == 3
    # the pipeline's dump → validate round trip keeps them
    again = DiagnosisSpec.model_validate(given.model_dump())
    assert again.baseline_seeds == [5, 7, 9] and again.ensemble.members == 3


def test_same_seed_same_members_and_results(healthy):
    spec = _spec((0, 1))
    a, b = member_configs(healthy, spec), member_configs(healthy, spec)
    assert [m.label for m in a] == [m.label for m in b]
    assert all(x.config.model_dump() == y.config.model_dump() and x.values == y.values
               for x, y in zip(a, b, strict=True))
    other = member_configs(healthy, spec, seed=1)
    assert other[0].values["speed_factor"] != a[0].values["speed_factor"]
    # adding members keeps the earlier ones
    more = member_configs(healthy, _spec((0, 1, 2)))
    assert [m.values for m in more[:4]] == [m.values for m in a]
    one = _spec((3,), measurements_per_run=1)
    first = [next(simulate_baseline(healthy, one, {"t_end_s": 0.5}))[1] for _ in range(2)]
    for name in ("sensors.ring_acc", "angle", "mesh_force"):
        assert np.array_equal(first[0][name].values[:2000], first[1][name].values[:2000])


def _uniform_ok(x: np.ndarray, tol: float) -> None:
    """Draws of U(1 − tol, 1 + tol): range, mean and variance within 4 standard errors."""
    n = x.size
    sigma = tol / math.sqrt(3)
    assert x.min() >= 1 - tol and x.max() <= 1 + tol
    assert x.min() < 1 - 0.9 * tol and x.max() > 1 + 0.9 * tol  # P(miss) = 0.95^N
    assert abs(x.mean() - 1) < 4 * sigma / math.sqrt(n)
    assert abs(x.var(ddof=1) / sigma**2 - 1) < 4 * math.sqrt(0.8 / n)


def test_draws_within_tolerance_and_spread_as_declared(healthy):
    ens = {"measurements_per_run": 2, "speed_tolerance": 0.03, "load_tolerance": 0.2,
           "error_scale_tolerance": 0.4, "pin_error_m": 20e-6,
           "transfer_path_tolerance": 0.15, "sensitivity_tolerance": 0.05,
           "noise_tolerance": 0.6}
    rnd = healthy.model_copy(update={"planetary_dynamics": healthy.planetary_dynamics.model_copy(
        update={"stages": [healthy.planetary_dynamics.stages[0].model_copy(
            update={"random_error_max_m": 1e-6})]})})
    members = [m for s in range(4) for m in member_configs(rnd, _spec(range(64), **ens), s)]
    runs = [m for m in members if m.measurement == 0]
    nom_sim = rnd.planetary_dynamics.simulation
    for m in members:
        v, c = m.values, m.config
        f, g, e = v["speed_factor"], v["load_factor"], v["error_scale"]
        sim = c.planetary_dynamics.simulation
        assert c.input_speeds_rpm["sun"] == pytest.approx(rnd.input_speeds_rpm["sun"] * f)
        for body, rpm in nom_sim.initial_speed_rpm.items():
            assert sim.initial_speed_rpm[body] == pytest.approx(rpm * f)
        assert sim.motor.rated_speed_rpm == pytest.approx(nom_sim.motor.rated_speed_rpm * f)
        assert sim.motor.frequency_hz == pytest.approx(nom_sim.motor.frequency_hz * f)
        assert sim.wheel_load.full_load_torque_nm == pytest.approx(
            nom_sim.wheel_load.full_load_torque_nm * g)
        sd = c.planetary_dynamics.stages[0]
        assert sd.random_error_max_m == pytest.approx(1e-6 * e)
        assert len(sd.pin_errors_m) == 3 and max(map(abs, sd.pin_errors_m)) <= 20e-6
        acc, nom = c.sensors[0], rnd.sensors[0]
        sv = v["sensors"]["ring_acc"]
        assert acc.noise_rms == pytest.approx(nom.noise_rms * sv["noise_factor"])
        mode, m0 = acc.transfer_path[0], nom.transfer_path[0]
        assert mode.frequency_hz == pytest.approx(m0.frequency_hz * sv["frequency_factor"][0])
        assert mode.damping_ratio == pytest.approx(m0.damping_ratio * sv["damping_factor"][0])
        assert mode.modal_mass_kg == pytest.approx(m0.modal_mass_kg / sv["gain_factor"])
        assert [s.seed for s in c.sensors] == [s.seed + m.measurement for s in rnd.sensors]
    _uniform_ok(np.array([m.values["speed_factor"] for m in runs]), 0.03)
    _uniform_ok(np.array([m.values["load_factor"] for m in runs]), 0.2)
    _uniform_ok(np.array([m.values["error_scale"] for m in runs]), 0.4)
    pins = np.concatenate([m.values["pin_errors_m"]["planetary"] for m in runs])
    _uniform_ok(1 + pins / 20e-6, 1.0)
    sens = [m.values["sensors"]["ring_acc"] for m in members]
    _uniform_ok(np.array([s["noise_factor"] for s in sens]), 0.6)
    _uniform_ok(np.array([s["frequency_factor"][0] for s in sens]), 0.15)
    _uniform_ok(np.array([s["damping_factor"][0] for s in sens]), 0.15)
    _uniform_ok(np.array([s["gain_factor"] for s in sens]), 0.05)
    # the measurements of one run share its dynamics draws, not their sensor draws
    assert members[0].values["speed_factor"] == members[1].values["speed_factor"]
    assert sens[0]["noise_factor"] != sens[1]["noise_factor"]


def test_zero_tolerances_give_the_nominal_machine(healthy):
    zero = {k: 0.0 for k in ("speed_tolerance", "load_tolerance", "error_scale_tolerance",
                             "pin_error_m", "transfer_path_tolerance", "sensitivity_tolerance",
                             "noise_tolerance")}
    m = member_configs(healthy, _spec((0,), measurements_per_run=1, **zero))[0]
    assert m.config.model_dump() == healthy.model_dump()


def test_fe_transmission_members():
    cfg = healthy_variant(load_config(FE))
    spec = _spec(range(16), measurements_per_run=1, bearing_clearance_tolerance=0.3)
    t0 = cfg.transmission
    for m in member_configs(cfg, spec):
        t, f, g = m.config.transmission, m.values["speed_factor"], m.values["load_factor"]
        assert abs(f - 1) <= 0.02 and abs(g - 1) <= 0.1
        assert t.speed_law.start_rpm == pytest.approx(t0.speed_law.start_rpm * f)
        assert t.speed_law.end_rpm == pytest.approx(t0.speed_law.end_rpm * f)
        assert t.speed_law.revolutions == t0.speed_law.revolutions
        assert t.load.torque_nm == pytest.approx(t0.load.torque_nm * g)
        assert m.config.input_speeds_rpm["input"] == pytest.approx(1000.0 * f)
        for b, b0 in zip(t.bearings, t0.bearings, strict=True):
            assert abs(b.diametral_clearance_m / b0.diametral_clearance_m - 1) <= 0.3
            assert m.values["bearing_clearance_m"][b.name] == b.diametral_clearance_m


def test_speed_changes_the_simulated_speed_by_the_drawn_factor(healthy):
    """The initial state is the config's rigid motion scaled by f and the drive (motor
    frequency, rated speed) is scaled with it, so over a 2 s run the mean speeds scale by f;
    the motor's slip and the speed-dependent wheel load move it by a fraction of the drawn
    deviation only (allowed: 5 % of |f − 1|)."""
    spec = _spec(range(6), measurements_per_run=1, load_tolerance=0.0)
    m = max(member_configs(healthy, spec), key=lambda x: abs(x.values["speed_factor"] - 1))
    f = m.values["speed_factor"]
    assert abs(f - 1) > 0.01
    bare = {"sensors": []}
    nom = run_simulation(healthy.model_copy(update=bare), seed=m.seed, t_end_s=2.0)
    run = run_simulation(m.config.model_copy(update=bare), seed=m.seed, t_end_s=2.0)
    for shaft in ("motor", "sun", "carrier"):
        ratio = float(run["speed_rpm"].sel(shaft=shaft).mean()
                      / nom["speed_rpm"].sel(shaft=shaft).mean())
        assert abs(ratio - f) < 0.05 * abs(f - 1), shaft


def test_remeasurement_reuses_the_dynamics(healthy):
    spec = _spec((2,), measurements_per_run=2)
    (m0, d0), (m1, d1) = list(simulate_baseline(healthy, spec, {"t_end_s": 1.0}))
    assert d0.attrs["ensemble_member"] == m0.label and m1.measurement == 1
    for name in ("angle", "speed", "mesh_force"):
        assert np.shares_memory(d0[name].values, d1[name].values)
    assert not np.array_equal(d0["sensors.ring_acc"].values, d1["sensors.ring_acc"].values)
    # independent path: a full run of the member's config measures the same bits
    ref = run_simulation(m1.config, seed=m1.seed, t_end_s=1.0)
    for name in ("sensors.ring_acc", "sensors.carrier_enc", "angle"):
        assert np.array_equal(ref[name].values, d1[name].values), name


@pytest.mark.parametrize(("entry", "value", "words"), [
    ("members", 0, ("diagnosis.ensemble.members", "1")),
    ("members", 65, ("diagnosis.ensemble.members", "64")),
    ("measurements_per_run", 0, ("diagnosis.ensemble.measurements_per_run",)),
    ("speed_tolerance", 0.7, ("diagnosis.ensemble.speed_tolerance", "0.5")),
    ("speed_tolerance", -0.01, ("diagnosis.ensemble.speed_tolerance", "0")),
    ("load_tolerance", float("nan"), ("diagnosis.ensemble.load_tolerance", "finite")),
    ("noise_tolerance", 1.5, ("diagnosis.ensemble.noise_tolerance", "1")),
    ("transfer_path_tolerance", 0.6, ("diagnosis.ensemble.transfer_path_tolerance",)),
    ("pin_error_m", -1e-6, ("diagnosis.ensemble.pin_error_m",)),
    ("pin_error_m", "3 kg", ("diagnosis.ensemble.pin_error_m",)),
    ("bearing_clearance_tolerance", 1.0, ("diagnosis.ensemble.bearing_clearance_tolerance",)),
    ("seed", -1, ("diagnosis.ensemble.seed",)),
    ("speed_tol", 0.1, ("diagnosis.ensemble.speed_tol", "unknown field")),
])
def test_bad_ensemble_values_name_the_field(entry, value, words):
    data = tomllib.loads(PLANETARY.read_text())
    data["diagnosis"]["ensemble"] = {entry: value}
    with pytest.raises(ConfigError) as exc:
        parse_config(data)
    assert all(w in str(exc.value) for w in words), str(exc.value)


@pytest.mark.parametrize(("entry", "value"), [
    ("false_alarm_probability", 0.0), ("false_alarm_probability", 0.25),
    ("localisation_confidence", 0.4), ("localisation_confidence", 1.0)])
def test_bad_probabilities_name_the_field(entry, value):
    data = tomllib.loads(PLANETARY.read_text())
    data["diagnosis"][entry] = value
    with pytest.raises(ConfigError, match=f"diagnosis.{entry}"):
        parse_config(data)


def test_a_perturbed_value_breaking_a_rule_names_the_member(healthy):
    """A damping ratio of 0.99 ± 10 % leaves (0, 1) for about half the draws (64 here):
    refused naming the field and the member."""
    s0 = healthy.sensors[0]
    damped = healthy.model_copy(update={"sensors": [s0.model_copy(update={
        "transfer_path": [s0.transfer_path[0].model_copy(update={"damping_ratio": 0.99})]}),
        *healthy.sensors[1:]]})
    with pytest.raises(ConfigError) as exc:
        member_configs(damped, _spec(range(32), transfer_path_tolerance=0.1))
    assert "baseline ensemble member run" in str(exc.value)
    assert "transfer_path[0].damping_ratio" in str(exc.value)
