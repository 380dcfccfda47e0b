"""Any rotor in the config (issue 24): plain discs, linear supports (constant, cross-coupled,
speed-tabulated), dashpots, a bare rotor without gears or Hertzian bearings, outputs by name.

Reference: ROSS 2.3.0 (ross-rotordynamics, run once in a separate venv with
``benchmarks/ross_rotor.py modal 12|24``; not a geardyn dependency), the same rotor
(examples/rotor_two_discs.toml): damped natural frequencies ``wn`` = |λ|/2π at rest and at
3000 rpm, and the steady unbalance response of disc 1. Tolerances: 1e-8 relative on the
frequencies (both codes assemble the same Timoshenko/Nelson element, Cowper shear coefficient;
the values are typed to 8 decimals) and 1e-6 on the complex response (typed in full; it
agrees to 3e-11)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn import load_config
from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError
from geardyn.models.transmission import build_model, prepare, simulate
from geardyn.models.transmission.modal import damped_modes, unbalance_response

# ROSS 2.3.0, Rotor.run_modal(speed, num_modes=40, sparse=False).wn / 2π [Hz], first ten
ROSS_WN = {
    (12, 0): [62.27020911, 62.27020911, 208.95186589, 208.95186589, 462.04520942, 462.04520942,
              612.36276491, 612.36276491, 622.57747617, 917.58303462],
    (12, 3000): [62.12305077, 62.41621825, 208.18786591, 209.69568535, 458.43104828,
                 465.59091351, 610.91413878, 613.83530202, 622.57747617, 904.12532167],
    (24, 0): [62.27007028, 62.27007028, 208.94520275, 208.94520275, 462.01956295, 462.01956295,
              612.39870072, 612.39870072, 622.54552238, 917.35026623],
    (24, 3000): [62.12291299, 62.41607833, 208.18129188, 209.68893516, 458.40235871,
                 465.56826614, 610.94962812, 613.871659, 622.54552238, 903.92972687],
}
# ROSS 2.3.0, run_unbalance_response(node of disc 1, 1e-4, 0, frequency=[3000 rpm]):
# forced_resp of disc 1's x [m] (real, imaginary)
ROSS_UNBALANCE_X = {12: (8.297948200121246e-06, -6.801522179420464e-07),
                    24: (8.297989303795638e-06, -6.8015936834851e-07)}


def _rotor(examples_dir, elements: int = 12, **edit) -> dict:
    d = load_config(examples_dir / "rotor_two_discs.toml").model_dump(exclude_none=True)
    t = d["transmission"]
    t["shafts"][0]["elements"] = elements
    t["discs"][0]["at"]["node"] = elements // 3
    t["discs"][1]["at"]["node"] = 3 * elements // 4
    t["supports"][1]["at"]["node"] = elements
    t["unbalance"][0]["at"]["node"] = elements // 3
    t.update(edit)
    return d


@pytest.mark.parametrize("elements", [12, 24])
def test_rotor_from_config_matches_ross(examples_dir, elements) -> None:
    cfg = parse_config(_rotor(examples_dir, elements))
    model = build_model(cfg)
    prep = prepare(model)
    for rpm in (0, 3000):
        wn, _, _ = damped_modes(model, prep, rpm)
        np.testing.assert_allclose(wn[:10] / (2 * math.pi), ROSS_WN[(elements, rpm)], rtol=1e-8)
    x = unbalance_response(model, prep, 3000.0, model.node_of("rotor", elements // 3), 1e-4)
    ref = complex(*ROSS_UNBALANCE_X[elements])
    assert abs(x[6 * model.node_of("rotor", elements // 3)] - ref) < 1e-6 * abs(ref)
    # invariant: isotropic rotor, forward circular whirl y = −i x
    j = 6 * model.node_of("rotor", elements // 3)
    assert abs(x[j + 1] + 1j * x[j]) < 1e-9 * abs(x[j])


def test_bare_rotor_simulates_and_records_by_name(examples_dir) -> None:
    """Time integration of the bare rotor (no gears, no Hertzian bearings; it crashed before
    issue 24): after the transient the 1× amplitude of disc 1 equals the harmonic solution,
    the support forces are K u + C u̇ of the recorded node, and the energy balance closes."""
    d = _rotor(examples_dir)
    d["transmission"]["simulation"]["duration_s"] = 1.2
    d["transmission"]["simulation"]["integrator"] = "explicit"
    cfg = parse_config(d)
    ds = simulate(cfg)
    assert ds.attrs["status"] == "ok"
    t = ds.time.values
    x = ds.displacement.sel(dof="rotor.n4.x").values
    sel = t >= 0.8
    w = 100 * math.pi
    amp = 2 * abs(np.mean(x[sel] * np.exp(-1j * w * t[sel])))
    model = build_model(cfg)
    ref = abs(unbalance_response(model, prepare(model), 3000.0, 4, 1e-4)[24])
    # the slowest transient (62 Hz, ζ ≈ 0.02) has decayed to < 1e-4 after 0.8 s
    assert amp == pytest.approx(ref, rel=2e-3)
    f = ds.support_force.sel(support="left").values
    u = ds.displacement.sel(dof=["rotor.n0.x", "rotor.n0.y"]).values
    ud = ds.velocity.sel(dof=["rotor.n0.x", "rotor.n0.y"]).values
    np.testing.assert_allclose(f, 1e7 * u + 5e3 * ud, rtol=1e-12, atol=1e-12)
    assert set(ds.support.values) == {"left", "right"}
    assert ds.bearing_force.shape == (t.size, 0, 2)


def test_record_names_refused_with_the_field(examples_dir) -> None:
    d = _rotor(examples_dir)
    d["transmission"]["simulation"]["record"] = ["nowhere"]
    d["transmission"]["simulation"]["duration_s"] = 1e-3
    with pytest.raises(ConfigError, match=r"simulation.record\[0\]: 'nowhere'"):
        simulate(parse_config(d))


def test_ball_clearance_beyond_groove_distance_refused(examples_dir) -> None:
    d = load_config(examples_dir / "seed002_transmission.toml").model_dump(exclude_none=True)
    b = d["transmission"]["bearings"][0]
    limit = 2 * (b["inner_conformity"] + b["outer_conformity"] - 1) * b["element_diameter_m"]
    b["diametral_clearance_m"] = 1.01 * limit
    with pytest.raises(ConfigError, match="diametral_clearance_m.*2 \\(f_i \\+ f_o − 1\\) D"):
        parse_config(d)


def _support_stiffness(model) -> np.ndarray:  # noqa: ANN001
    s = model.supports[0]
    return s.K, s.C


def test_speed_tabulated_support_interpolated(examples_dir) -> None:
    """Coefficients against speed (ROSS's BearingElement ``frequency``): linear interpolation
    at the run's shaft speed, held outside the table; cross terms give a non-symmetric K."""
    d = _rotor(examples_dir)
    s = d["transmission"]["supports"][0]
    s.update(speeds_rpm=[1000.0, 5000.0], kxx_n_per_m=[1e7, 3e7], kyy_n_per_m=[1e7, 3e7],
             kxy_n_per_m=[0.0, 4e6], cxx_ns_per_m=[5e3, 1e3])
    model = build_model(parse_config(d))
    K, C = _support_stiffness(model)
    # 3000 rpm: halfway in the table
    assert K[0, 0] == pytest.approx(2e7) and K[0, 1] == pytest.approx(2e6)
    assert K[1, 0] == 0.0 and C[0, 0] == pytest.approx(3e3)
    j = 6 * model.supports[0].node
    assert model.K[j, j + 1] - model.K[j + 1, j] == pytest.approx(2e6)
    d["transmission"]["simulation"]["initial_rpm"] = 9000.0
    assert _support_stiffness(build_model(parse_config(d)))[0][0, 0] == pytest.approx(3e7)
    s["kxx_n_per_m"] = [1e7]
    with pytest.raises(ConfigError, match="kxx_n_per_m: 1 values for 2 speeds_rpm"):
        parse_config(d)


def test_cross_coupled_support_runs_explicit_like_harmonic(examples_dir) -> None:
    """Anisotropic supports with unequal cross terms (kxy ≠ kyx, cxy ≠ cyx): the explicit loop
    (non-symmetric K and C, transposed for its column passes) reaches the harmonic solution
    (every mode damped, the slowest with ζ = 0.009 at 64 Hz: < 2e-3 left after 0.5 s)."""
    d = _rotor(examples_dir)
    for s in d["transmission"]["supports"]:
        s.update(kyy_n_per_m=1.5e7, kxy_n_per_m=1e6, kyx_n_per_m=5e5, cxy_ns_per_m=300.0)
    d["transmission"]["simulation"].update(duration_s=1.0, integrator="explicit",
                                           record=["disc 1"])
    cfg = parse_config(d)
    ds = simulate(cfg)
    t = ds.time.values
    x = ds.displacement.sel(dof="rotor.n4.x").values
    y = ds.displacement.sel(dof="rotor.n4.y").values
    sel = t >= 0.5
    e = np.exp(-1j * 100 * math.pi * t[sel])
    model = build_model(cfg)
    ref = unbalance_response(model, prepare(model), 3000.0, 4, 1e-4)
    assert 2 * np.mean(x[sel] * e) == pytest.approx(ref[24], rel=3e-3)
    assert 2 * np.mean(y[sel] * e) == pytest.approx(ref[25], rel=3e-3)


def test_disc_geometry_offset_and_dashpot(examples_dir) -> None:
    """Disc from its geometry (ρπ(R² − r²)w, I_p, I_d); an axial offset e moves the disc's
    diametral inertia to I_d + m e² at the node (rigid link); a grounded dashpot adds c on its
    DOF only."""
    d = _rotor(examples_dir)
    t = d["transmission"]
    t["discs"][1] = {"name": "disc 2", "at": {"shaft": "rotor", "node": 9},
                     "outer_diameter_m": 0.2, "inner_diameter_m": 0.05, "width_m": 0.04,
                     "offset_m": 0.03}
    t["dashpots"] = [{"name": "damper", "at": {"shaft": "rotor", "node": 6}, "dof": "y",
                      "damping": 200.0}]
    base = build_model(parse_config(_rotor(examples_dir)))
    model = build_model(parse_config(d))
    m = 7810 * math.pi * (0.1**2 - 0.025**2) * 0.04
    idia = m * (0.1**2 + 0.025**2) / 4 + m * 0.04**2 / 12
    j = 6 * 9
    shaft_m = base.M[j, j] - 3.68
    assert model.M[j, j] - shaft_m == pytest.approx(m, rel=1e-12)
    shaft_i = base.M[j + 3, j + 3] - 0.0046763848501848275
    assert model.M[j + 3, j + 3] - shaft_i == pytest.approx(idia + m * 0.03**2, rel=1e-12)
    assert model.M[j, j + 4] - base.M[j, j + 4] == pytest.approx(m * 0.03, rel=1e-12)
    C = model.C_lin - base.C_lin
    assert C[6 * 6 + 1, 6 * 6 + 1] == 200.0 and np.count_nonzero(C) == 1
    # lumped shaft mass keeps the offset disc's coupling
    from geardyn.models.transmission.simulate import with_mass

    t["mass"] = "lumped"
    lumped = with_mass(model, parse_config(d).transmission)
    assert lumped.M[j, j + 4] == pytest.approx(m * 0.03, rel=1e-12)
    assert lumped.M[j + 1, j + 3] == pytest.approx(-m * 0.03, rel=1e-12)


@pytest.mark.parametrize("integrator", ["explicit", "newmark"])
def test_speed_table_followed_along_a_ramp(examples_dir, integrator) -> None:
    """Supports tabulated against speed (kyy 1e7 → 4e7 N/m from 0 to 3000 rpm) on a run-up
    600 → 3000 rpm under a constant 1000 N at midspan: statically determinate, each support
    carries 500 N, so its node sinks by 500/k_yy(n) at the current speed n (quasi-static: the
    1 s ramp is slow against the 62 Hz mode; modal damping 0.1 so that the bending transient of
    the suddenly applied load is gone after 0.6 s: the stiff supports alone hardly damp it) and
    the recorded support force (K(n) u + C(n) u̇) stays 500 N."""
    d = _rotor(examples_dir)
    t = d["transmission"]
    for s in t["supports"]:
        s.update(speeds_rpm=[0.0, 3000.0], kyy_n_per_m=[1e7, 4e7])
    t["unbalance"] = []
    t["modal_damping"] = 0.1
    t["external_loads"] = [{"at": {"shaft": "rotor", "node": 6}, "dof": "y", "value": -1000.0}]
    t["speed_law"] = {"reference": {"shaft": "rotor", "node": 0}, "start_rpm": 600.0,
                      "end_rpm": 3000.0, "revolutions": 30.0}
    t["simulation"].update(integrator=integrator, record=["left"], duration_s=None,
                           initial_rpm=None)
    ds = simulate(parse_config(d))
    assert ds.attrs["status"] == "ok" and ds.attrs["integrator"] == integrator
    time = ds.time.values
    sel = time > 0.6
    n = np.abs(ds.velocity.sel(dof="rotor.n0.rz").values[sel]) * 30 / math.pi
    assert n.min() < 2200 and n.max() > 2900  # the ramp is followed
    k = np.interp(n, [0.0, 3000.0], [1e7, 4e7])
    uy = ds.displacement.sel(dof="rotor.n0.y").values[sel]
    np.testing.assert_allclose(uy, -500.0 / k, rtol=2e-3)
    fy = ds.support_force.sel(support="left", axis="y").values[sel]
    np.testing.assert_allclose(fy, -500.0, rtol=2e-3)


def test_modal_strain_energy_includes_the_supports(examples_dir) -> None:
    """Invariant (seed 003 eqs 3.28-3.29 on the element matrices): the strain energy of every
    elastic mode over the shaft elements and the supports sums to ½ ω² (mass-normalised)."""
    from geardyn.models.transmission.modal import fe_modes

    model = build_model(parse_config(_rotor(examples_dir)))
    r = fe_modes(model, prepare(model))
    assert r.spring_names[-2:] == ["support.left", "support.right"]
    el = r.freq_hz > 1.0
    np.testing.assert_allclose(r.strain[el].sum(axis=1),
                               0.5 * (2 * math.pi * r.freq_hz[el]) ** 2, rtol=1e-8)
    assert r.strain[np.argmax(el), -2:].sum() > 0.1 * r.strain[np.argmax(el)].sum()
