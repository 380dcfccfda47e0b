"""Modal (exponential, port-force) integration of the FE transmission (issue 24): its one-mode
coefficients against closed forms, the linear structure against the exact state-space
solution, the nonlinear seed 002 run against a fine explicit reference, stop/resume, refusals
and the step criterion."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from geardyn import load_config
from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError
from geardyn.models.transmission import build_model, prepare, simulate
from geardyn.solve.control import RunControl
from geardyn.solve.modal_fe import modal_coefficients


def test_one_mode_step_response_is_the_closed_form() -> None:
    """Constant force P on η̈ + 2ζω η̇ + ω² η = P from rest: η(t) = P/ω² (1 − e^{−ζωt}
    (cos ω_d t + ζω/ω_d sin ω_d t)) (Chopra, *Dynamics of Structures*, 2012, eq 4.3.2);
    any step, to rounding (1e-12 of the static deflection)."""
    w, z, P = 2 * math.pi * 50.0, 0.05, 3.0
    wd = w * math.sqrt(1 - z * z)
    for h in (1e-4, 3e-3, 0.05):  # ωh from 0.03 to 16: no step limit
        cf = modal_coefficients(np.array([w * w]), np.array([2 * z * w]), h)[:, :, 0]
        eta, deta = 0.0, 0.0
        for k in range(1, 6):
            eta, deta = (cf[0, 0] * eta + cf[0, 1] * deta + (cf[0, 2] + cf[0, 3] + cf[0, 4]) * P,
                         cf[1, 0] * eta + cf[1, 1] * deta + (cf[1, 2] + cf[1, 3] + cf[1, 4]) * P)
            t = k * h
            ref = P / w**2 * (1 - math.exp(-z * w * t) * (math.cos(wd * t)
                                                          + z * w / wd * math.sin(wd * t)))
            assert abs(eta - ref) < 1e-12 * P / w**2


@pytest.mark.parametrize("w2", [(2 * math.pi * 80.0) ** 2, 0.0, -3.0])
def test_one_mode_quadratic_hold_matches_solve_ivp(w2: float) -> None:
    """The hold through p₋₁, p₀, p₁ (quadratic in t): the step and the state a third into it
    equal an accurate Runge-Kutta solution (DOP853, rtol 1e-12) to 1e-9; elastic, rigid
    (ω² = 0) and slightly unstable (ω² < 0, a rigid mode of a linearised pencil) modes."""
    h, c = 2e-3, 4.0
    pm, p0, p1 = 1.0, -2.0, 0.5
    a, b, c2 = p0, 0.5 * (p1 - pm), 0.5 * (p1 - 2 * p0 + pm)

    def rhs(t: float, y: np.ndarray) -> list[float]:
        s = t / h
        return [y[1], a + b * s + c2 * s * s - c * y[1] - w2 * y[0]]

    y0 = np.array([0.3, -1.2])
    for tau in (h, h / 3):
        cf = modal_coefficients(np.array([w2]), np.array([c]), h, tau)[:, :, 0]
        got = cf[:, 0] * y0[0] + cf[:, 1] * y0[1] + cf[:, 2] * pm + cf[:, 3] * p0 + cf[:, 4] * p1
        ref = solve_ivp(rhs, (0, tau), y0, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
        assert np.allclose(got, ref, rtol=1e-9, atol=1e-12)


def _linear_rotor(examples_dir, **sim):  # noqa: ANN001, ANN202
    d = load_config(examples_dir / "rotor_two_discs.toml").model_dump(exclude_none=True)
    t = d["transmission"]
    t["modal_damping"] = 0.02
    for s in t["supports"]:
        s["cxx_ns_per_m"] = s["cyy_ns_per_m"] = 0.0
    t.pop("unbalance")
    t["drive"] = {"at": {"shaft": "rotor", "node": 0}, "torque_nm": 40.0}
    t["load"] = {"at": {"shaft": "rotor", "node": 12}, "torque_nm": 10.0}
    t["simulation"].update(gyroscopic=False, duration_s=0.05, record_rate_hz=5000.0,
                           record=["rotor.n4.rz", "rotor.n12.rz"], integrator="modal", **sim)
    return parse_config(d)


def test_linear_structure_is_integrated_exactly(examples_dir) -> None:
    """Bare rotor (modal damping 2 %, supports without damping), drive 40 N·m and load
    10 N·m from 3000 rpm: the twist between the shaft's ends and the speed equal the exact
    state-space solution exp(A t) x₀ (full 2n system, independent of the modes) to 1e-7 of
    their range, at the default step (10 shaft orders, 4 steps per period: 0.5 ms, records
    every 0.2 ms inside the steps) — no step limit from the 27 kHz torsional/axial modes."""
    cfg = _linear_rotor(examples_dir)
    ds = simulate(cfg)
    assert ds.attrs["integrator"] == "modal" and ds.attrs["status"] == "ok"
    assert ds.attrs["time_step_s"] == pytest.approx(5e-4)
    assert np.allclose(np.diff(ds.time.values), 2e-4, rtol=1e-9, atol=0)
    model = build_model(cfg)
    prep = prepare(model)
    n = model.ndof
    Mi = np.linalg.inv(model.M)
    F = np.zeros(n)
    F[6 * model.drive_node + 5] = 40.0 * model.node_sign(model.drive_node)
    F[6 * model.load_node + 5] = -10.0 * model.node_sign(model.load_node)
    A = np.zeros((2 * n + 1, 2 * n + 1))
    A[:n, n : 2 * n] = np.eye(n)
    A[n : 2 * n, :n] = -Mi @ model.K
    A[n : 2 * n, n : 2 * n] = -Mi @ np.asarray(prep.C)
    A[n : 2 * n, 2 * n] = Mi @ F
    v0 = np.zeros(n)
    v0[5::6] = 100 * math.pi
    x0 = np.r_[prep.q0, v0, 1.0]
    X = np.array([expm(A * t) @ x0 for t in ds.time.values])
    i4, i12 = (model.dof_names.index(k) for k in ("rotor.n4.rz", "rotor.n12.rz"))
    got = ds.displacement.sel(dof=["rotor.n4.rz", "rotor.n12.rz"]).values
    twist, ref = got[:, 0] - got[:, 1], X[:, i4] - X[:, i12]
    assert np.abs(twist - ref).max() < 1e-7 * np.ptp(ref)
    speed = ds.velocity.sel(dof="rotor.n4.rz").values
    assert np.abs(speed - X[:, n + i4]).max() < 1e-7 * np.ptp(X[:, n + i4])


def _seed002(examples_dir, **sim):  # noqa: ANN001, ANN202
    d = load_config(examples_dir / "seed002_transmission.toml").model_dump(exclude_none=True)
    t = d["transmission"]
    return parse_config({**d, "transmission": {**t, "simulation": {**t["simulation"], **sim}}})


def test_seed002_default_is_modal_and_more_accurate_than_explicit(examples_dir) -> None:
    """Seed 002, 2 revolutions at 360 rpm: against a fine explicit reference (h = 2 µs), the
    default (modal, 30 µs: one step per point of the stiffness table at the top mesh
    frequency, records at 50 kHz) is at least as accurate as the explicit loop at its
    stability step (the integrator of the seed 002 validations until issue 24): rms error of
    the worst mesh force (0.38 % against 0.57 %), of the worst bearing load (0.53 % against
    0.61 %; bearing loads between steps are interpolated linearly) and of the output speed
    fluctuation (1.6 % against 5.3 %)."""
    model = build_model(_seed002(examples_dir))
    prep = prepare(model, "output")
    runs = {k: simulate(_seed002(examples_dir, **sim), revolutions=2.0, prepared=prep,
                        model=model)
            for k, sim in (("ref", {"integrator": "explicit", "time_step_s": 2e-6}),
                           ("explicit", {"integrator": "explicit"}), ("auto", {}))}
    auto = runs["auto"]
    assert auto.attrs["integrator"] == "modal" and auto.attrs["status"] == "ok"
    assert auto.attrs["time_step_s"] > 3 * runs["explicit"].attrs["time_step_s"]
    assert np.allclose(np.diff(auto.time.values), 2e-5, rtol=1e-9, atol=0)
    t = runs["ref"].time.values
    sel = (t > 0.3 * t[-1]) & (t < 0.98 * t[-1])

    def errors(x) -> np.ndarray:  # noqa: ANN001
        out = []
        for var in ("mesh_force", "bearing_load"):  # the worst mesh, the worst bearing
            a = runs["ref"][var].values[sel]
            b = x[var].interp(time=t).values[sel]
            out.append(np.max(np.sqrt(np.mean((a - b) ** 2, axis=0) / np.mean(a**2, axis=0))))
        sp = runs["ref"].speed.sel(shaft="output").values[sel]
        sb = x.speed.sel(shaft="output").interp(time=t).values[sel]
        ac = sp - np.polyval(np.polyfit(t[sel], sp, 2), t[sel])
        return np.array([*out, np.sqrt(np.mean((sp - sb) ** 2)) / np.std(ac)])

    e_exp, e_mod = errors(runs["explicit"]), errors(auto)
    assert np.all(e_exp < 0.1)
    assert np.all(e_mod <= e_exp), (e_mod, e_exp)
    # the energy balance closes as for the other integrators (status ok checked above)


def test_modal_stop_and_resume_bit_identical(examples_dir) -> None:
    """A stopped modal run (seed 002, 0.3 revolution, steps of 3 ticks with records inside
    them) resumes from its checkpoint to the same bits as the uninterrupted run."""
    cfg = _seed002(examples_dir)
    prep = prepare(build_model(cfg), "output")
    full = simulate(cfg, revolutions=0.3, prepared=prep)
    assert full.attrs["integrator"] == "modal"
    saved: list[dict] = []

    def progress(_f: float) -> None:
        ctl.request_stop("test stop")

    ctl = RunControl(progress=progress, checkpoint=lambda s: saved.append(
        {k: np.array(v, copy=True) if isinstance(v, np.ndarray) else v for k, v in s.items()}))
    part = simulate(cfg, revolutions=0.3, prepared=prep, control=ctl)
    assert part.attrs["status"] == "interrupted"
    res = simulate(cfg, revolutions=0.3, prepared=prep, control=RunControl(resume=saved[-1]))
    for name in full.data_vars:
        assert np.array_equal(res[name].values, full[name].values), name
    assert res.attrs["energy_input_J"] == full.attrs["energy_input_J"]


def test_modal_refused_where_it_does_not_apply(examples_dir) -> None:
    cfg = _seed002(examples_dir, integrator="modal", gyroscopic=True)
    with pytest.raises(ConfigError, match="'modal' needs modal damping.*gyroscopic"):
        simulate(cfg, revolutions=0.01)
    rotor = load_config(examples_dir / "rotor_two_discs.toml").model_dump(exclude_none=True)
    rotor["transmission"]["simulation"].update(integrator="modal", gyroscopic=False)
    rotor["transmission"].pop("unbalance")
    with pytest.raises(ConfigError, match="support or dashpot damping"):
        simulate(parse_config(rotor))


def test_modal_step_follows_the_speed_up_to_the_structural_frequency() -> None:
    """``structural_frequency_hz``: the step follows the speed (one step per stiffness-table
    point at the current mesh frequency) but never exceeds 1/(4 f_s), nor falls below the
    step at the top speed; without it the step of the top speed holds for the whole run."""
    from types import SimpleNamespace

    from geardyn.models.transmission.simulate import modal_step

    sim = SimpleNamespace(record_rate_hz=50_000.0, time_step_s=None, resolved_frequency_hz=None,
                          structural_frequency_hz=None)
    period = 1.0 / 1041.0  # top mesh frequency 1041 Hz, 64 table points: h = 15 µs

    def ratio(t: float) -> float:  # 200 → 900 rpm over 1 s
        return (200.0 + 700.0 * t) / 900.0

    tick, per_rec, schedule, h = modal_step(sim, period, 30.0, 64.0, ratio)
    assert (tick, per_rec) == pytest.approx((5e-6, 4)) and h == pytest.approx(15e-6)
    assert schedule(0.0, 0.02) == schedule(0.98, 1.0) == 3
    sim.structural_frequency_hz = 12_500.0  # steps of at most 20 µs
    tick, per_rec, schedule, h = modal_step(sim, period, 30.0, 64.0, ratio)
    assert h == pytest.approx(15e-6)
    assert schedule(0.0, 0.02) == 4  # 200 rpm: the table allows 67 µs, f_s 20 µs
    assert schedule(0.98, 1.0) == 3  # top speed: the table's 15 µs
    sim.structural_frequency_hz = 1e6  # above the top-speed criterion: the top-speed step
    assert modal_step(sim, period, 30.0, 64.0, ratio)[2](0.0, 0.02) == 3


def test_seed002_run_up_with_speed_following_step(examples_dir) -> None:
    """Seed 002 run-up 200 → 900 rpm over 3 revolutions with ``structural_frequency_hz`` =
    12.5 kHz (steps of 20 µs at low speed, 15 µs at the top): fewer steps than the constant
    default, energy balance closed (status ok), and against a fine explicit reference
    (h = 2 µs) errors within those of the explicit loop at its stability step (rms of the worst
    mesh force, worst bearing load, output speed fluctuation — measured: 0.27 %, 2.3 %, 0.9 %
    against the explicit loop's 2.0 %, 2.8 %, 8.2 %; the constant 15 µs step: 0.27 %, 1.1 %,
    0.6 %)."""
    d = load_config(examples_dir / "seed002_transmission.toml").model_dump(exclude_none=True)
    d["transmission"]["speed_law"].update(start_rpm=200.0, end_rpm=900.0, revolutions=3.0)
    model = build_model(parse_config(d))
    prep = prepare(model, "output")

    def run(**sim):  # noqa: ANN003, ANN202
        t = d["transmission"]
        c = parse_config({**d, "transmission": {**t, "simulation": {**t["simulation"], **sim}}})
        return simulate(c, prepared=prep, model=model)

    runs = {"ref": run(integrator="explicit", time_step_s=2e-6), "explicit": run(
        integrator="explicit"), "const": run(), "follow": run(structural_frequency_hz=12_500.0)}
    assert runs["follow"].attrs["status"] == "ok"
    assert runs["follow"].attrs["steps"] < 0.9 * runs["const"].attrs["steps"]
    t = runs["ref"].time.values
    sel = (t > 0.1 * t[-1]) & (t < 0.98 * t[-1])

    def errors(x) -> np.ndarray:  # noqa: ANN001
        out = []
        for var in ("mesh_force", "bearing_load"):
            a = runs["ref"][var].values[sel]
            b = x[var].interp(time=t).values[sel]
            out.append(np.max(np.sqrt(np.mean((a - b) ** 2, axis=0) / np.mean(a**2, axis=0))))
        sp = runs["ref"].speed.sel(shaft="output").values[sel]
        sb = x.speed.sel(shaft="output").interp(time=t).values[sel]
        ac = sp - np.polyval(np.polyfit(t[sel], sp, 2), t[sel])
        return np.array([*out, np.sqrt(np.mean((sp - sb) ** 2)) / np.std(ac)])

    e = {k: errors(v) for k, v in runs.items() if k != "ref"}
    assert np.all(e["follow"] <= e["explicit"]), e


def test_resume_refused_with_another_step_schedule(examples_dir) -> None:
    """A checkpoint of a run-up with the speed-following step (``structural_frequency_hz``)
    does not resume the same run with the constant step: InputError naming the schedule."""
    from geardyn.errors import InputError

    d = load_config(examples_dir / "seed002_transmission.toml").model_dump(exclude_none=True)
    d["transmission"]["speed_law"].update(start_rpm=200.0, end_rpm=900.0, revolutions=1.0)
    t = d["transmission"]
    follow = parse_config({**d, "transmission": {**t, "simulation": {
        **t["simulation"], "structural_frequency_hz": 12_500.0}}})
    saved: list[dict] = []

    def progress(_f: float) -> None:
        ctl.request_stop("test stop")

    ctl = RunControl(progress=progress, checkpoint=lambda s: saved.append(dict(s)))
    assert simulate(follow, control=ctl).attrs["status"] == "interrupted"
    with pytest.raises(InputError, match="another run .*schedule"):
        simulate(parse_config(d), control=RunControl(resume=saved[-1]))
