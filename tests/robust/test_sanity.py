"""Issue 13: time step checked before the run, energy balance and mesh deflection after it.

References: the closed-form response of a damped single-degree-of-freedom oscillator under a
step force (energies in closed form / by quadrature of the closed-form velocity), the natural
period 2π√(m/k), the eigenvalues of the planetary model's own stiffness and mass matrices, and
the explicit stability limit 2/ω_max.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import quad

from geardyn.config import load_config
from geardyn.config.loader import parse_config
from geardyn.errors import InputError
from geardyn.run import run_simulation
from geardyn.solve.integrate import Drives, LinearSystem, VarSprings, newmark
from geardyn.solve.sanity import (
    TimeStepWarning,
    check_energy,
    check_time_step,
    energy_residual,
    shortest_period,
)

M, K, ZETA, F = 2.0, 8e4, 0.05, 100.0  # kg, N/m, 1, N
W = math.sqrt(K / M)  # 200 rad/s
C = 2 * ZETA * M * W


def _sdof() -> LinearSystem:
    return LinearSystem(np.array([[M]]), np.array([[C]]), np.array([[K]]), VarSprings.empty(1),
                        Drives.build([]), np.array([0.0]), np.array([[F]]))


def _closed_form(t: float) -> tuple[float, float]:
    """x(t), v(t) of m ẍ + c ẋ + k x = F from rest (underdamped step response)."""
    wd = W * math.sqrt(1 - ZETA**2)
    e = math.exp(-ZETA * W * t)
    x = F / K * (1 - e * (math.cos(wd * t) + ZETA / math.sqrt(1 - ZETA**2) * math.sin(wd * t)))
    v = F / K * W / math.sqrt(1 - ZETA**2) * e * math.sin(wd * t)
    return x, v


def test_energy_terms_match_closed_form_sdof():
    """Applied work F x(T), dissipated work ∫c v² dt (quadrature of the closed-form v),
    kinetic ½mv(T)² and potential ½kx(T)² of a step-loaded damped oscillator; ωΔt = 0.02
    (Newmark's phase error ~ (ωΔt)²/12 per radian: tolerance 1e-3 of the applied work)."""
    t_end = 0.05  # 1.6 periods: the motion is still large
    res = newmark(_sdof(), np.zeros(1), np.zeros(1), t_end, 1e-4)
    x, v = _closed_form(t_end)
    w_diss = quad(lambda t: C * _closed_form(t)[1] ** 2, 0.0, t_end, limit=200)[0]
    e = res.energy
    scale = F * x
    assert e["applied_J"] == pytest.approx(F * x, abs=1e-3 * scale)
    assert e["dissipated_J"] == pytest.approx(w_diss, abs=1e-3 * scale)
    assert e["kinetic_end_J"] == pytest.approx(0.5 * M * v * v, abs=1e-3 * scale)
    assert e["potential_end_J"] == pytest.approx(0.5 * K * x * x, abs=1e-3 * scale)
    assert e["kinetic_start_J"] == 0.0 and e["potential_start_J"] == 0.0
    res_j, scale_j = energy_residual(e)
    assert abs(res_j) < 1e-4 * scale_j and check_energy(e) == ""


def test_energy_check_flags_a_coarse_step():
    """The trapezoidal work balance of the SDOF closes to second order in ωΔt (residual ratio
    9 between ωΔt = 0.6 and 0.2, within 6-12) and is flagged (> 5 % of the energy exchanged) at
    ωΔt = 6, about one step per period."""
    rel = {}
    for wdt in (0.2, 0.6, 6.0):
        e = newmark(_sdof(), np.zeros(1), np.zeros(1), 0.1, wdt / W).energy
        r, s = energy_residual(e)
        rel[wdt] = abs(r) / s
        assert (check_energy(e) == "") == (wdt < 1)
    assert rel[0.2] < 1e-3
    assert 6 < rel[0.6] / rel[0.2] < 12
    assert rel[6.0] > 0.05


def test_time_step_limits_sdof():
    """Shortest period of the SDOF = 2π√(m/k); refused above 2 periods per step, warned
    between ½ and 2 periods per step and for fewer than 20 steps per mesh cycle."""
    t_n = 2 * math.pi * math.sqrt(M / K)
    assert shortest_period(_sdof()) == pytest.approx(t_n, rel=1e-12)
    with pytest.raises(InputError, match=r"sim.dt_s: the time step .* too large: the shortest "
                       r"natural period is 0.03142 s .*limit dt ≤ 0.06283 s"):
        check_time_step(2.1 * t_n, "sim.dt_s", shortest_period_s=t_n)
    with pytest.warns(TimeStepWarning, match="sim.dt_s: coarse time step"):
        check_time_step(0.6 * t_n, "sim.dt_s", shortest_period_s=t_n)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check_time_step(0.4 * t_n, "sim.dt_s", shortest_period_s=t_n) == []
    with pytest.raises(InputError, match="mesh stiffness would alias"):
        check_time_step(1e-3, "sim.dt_s", mesh_period_s=1.9e-3)
    with pytest.warns(TimeStepWarning, match="steps per mesh cycle"):
        check_time_step(1e-4, "sim.dt_s", mesh_period_s=1.9e-3)
    with pytest.raises(InputError, match="above the stability limit"):
        check_time_step(2e-5, "t.time_step_s", stable_limit_s=1e-5)


def test_planetary_hundredfold_step_refused(examples_dir):
    """Issue 13: 100 × dt_s of the reclaimer example ran to 'ok' with 0.17 m mesh deflections.
    Now refused before the run, naming dt_s and the shortest natural period, which agrees with
    the eigenvalues of the planetary model's own (mean-stiffness) matrices within 1 %."""
    import scipy.linalg as sla

    from geardyn.models.planetary.build import model_from_config

    cfg = load_config(examples_dir / "planetary_reclaimer.toml")
    model = model_from_config(cfg)
    w2 = sla.eigh(model.stiffness_matrix(), model.mass_matrix(), eigvals_only=True)
    f_max = math.sqrt(w2.max()) / (2 * math.pi)
    d = cfg.model_dump(exclude_none=True)
    d["planetary_dynamics"]["simulation"].update(dt_s=1e-2, t_end_s=0.5)
    with pytest.raises(InputError, match=r"planetary_dynamics\.simulation\.dt_s: the time step "
                       r"0\.01 s is too large") as ei:
        run_simulation(parse_config(d))
    hz = float(str(ei.value).split(" s (")[1].split(" Hz")[0])
    assert hz == pytest.approx(f_max, rel=0.01)


def test_vibro_impact_energy_conserved_or_flagged():
    """Conservative vibro-impact oscillator (gear-rattle-like: 1 kg on a 1e3 N/m spring, a
    1e7 N/m contact behind a 1 mm gap with contact loss, 1 m/s initial speed, no damping): the
    energy stays ½mv₀² = 0.5 J. At ω_c·Δt = 0.03 the books close (kinetic + potential at the
    end = 0.5 J within 1e-4 J); at ω_c·Δt = 3.2 the contacts are stepped over, the step pumps
    energy in, and the balance is flagged."""
    def impact() -> LinearSystem:
        spring = VarSprings.build([dict(a=[1.0], b=[0.0], k=[1e7], e=[-1e-3],
                                        contact_loss=True)], 1)
        return LinearSystem(np.array([[1.0]]), np.zeros((1, 1)), np.array([[1e3]]), spring,
                            Drives.build([]), np.zeros(0), np.zeros((0, 1)))

    fine = newmark(impact(), np.zeros(1), np.array([1.0]), 0.5, 1e-5).energy
    assert fine["kinetic_end_J"] + fine["potential_end_J"] == pytest.approx(0.5, abs=1e-4)
    assert check_energy(fine) == ""
    coarse = newmark(impact(), np.zeros(1), np.array([1.0]), 0.5, 1e-3).energy
    assert coarse["kinetic_end_J"] + coarse["potential_end_J"] > 0.6
    assert "energy balance off" in check_energy(coarse)


def test_planetary_coarse_step_warns_and_suspect_keeps_result(examples_dir, monkeypatch):
    """lin_parker at 3 × its step is warned (1.24 steps per shortest period, 16.8 per mesh
    cycle) and still closes its energy balance (a steady run). A run failing the energy check
    ends 'suspect' with its whole result (check forced with a zero tolerance)."""
    import geardyn.run as run_mod

    cfg = load_config(examples_dir / "planetary_lin_parker.toml")
    d = cfg.model_dump(exclude_none=True)
    d["planetary_dynamics"]["simulation"]["dt_s"] = 6e-5
    coarse = parse_config(d)
    with pytest.warns(TimeStepWarning) as rec:
        ds = run_simulation(coarse)
    text = " | ".join(str(w.message) for w in rec)
    assert "coarse time step 6e-05 s: 1.24 steps per shortest natural period" in text
    assert "16.8 steps per mesh cycle" in text
    assert ds.attrs["status"] == "ok"
    monkeypatch.setattr(run_mod, "check_energy", lambda e: check_energy(e, tolerance=0.0))
    ds = run_simulation(cfg)
    assert ds.attrs["status"] == "suspect"
    assert "energy balance off" in ds.attrs["diagnosis"]
    assert ds.sizes["time"] == round(0.01 / 2e-5) + 1


def test_transmission_step_above_stability_limit_refused(examples_dir):
    """FE explicit scheme: a time_step_s above 2/ω_max of the linearised model is refused by
    run_simulation (and the CLI), naming the field and the limit."""
    from scipy.linalg import eigh

    from geardyn.models.transmission import build_model, prepare

    cfg = load_config(examples_dir / "seed002_transmission.toml")
    prep = prepare(build_model(cfg), "output")
    w2 = eigh(prep.K_lin, prep.model.M, eigvals_only=True)
    limit = 2 / math.sqrt(w2.max())
    d = cfg.model_dump(exclude_none=True)
    d["transmission"]["simulation"].update(integrator="explicit", time_step_s=5e-5)
    with pytest.raises(InputError, match=r"transmission\.simulation\.time_step_s: the time step "
                       rf"5e-05 s is too large: above the stability limit 2/ω_max = "
                       rf"{limit:.4g} s"):
        run_simulation(parse_config(d), revolutions=0.2)


def test_transmission_energy_balance_and_deflection_check(examples_dir):
    """The FE run's energy balance (input − output − Σ dissipation = Δ(kinetic + shaft
    elastic)) closes within 1e-3 of the energy exchanged; a mesh force whose deflection
    F/k̄ (k̄: mean of the pair-stiffness table) exceeds 0.1 module makes the run 'suspect'."""
    from geardyn.models.transmission import build_model
    from geardyn.models.transmission.simulate import _output_checks, energy_terms

    cfg = load_config(examples_dir / "seed002_transmission.toml")
    ds = run_simulation(cfg, revolutions=0.3)
    assert ds.attrs["status"] == "ok"
    r, s = energy_residual(energy_terms(ds))
    assert abs(r) < 1e-3 * s
    model = build_model(cfg)
    mh = model.meshes
    k0 = float(np.mean(mh.ks[0, : int(mh.tlen[0])].sum(axis=-1)))
    module = mh.geometry[0].normal_module
    f0 = float(np.abs(ds["mesh_force"].values[:, 0]).max())
    for frac, status in ((0.08, "ok"), (0.12, "suspect")):
        bad = ds.copy(deep=True)
        bad["mesh_force"][:, 0] *= frac * module * k0 / f0
        _output_checks(bad, model)
        assert bad.attrs["status"] == status
    assert f"mesh '{mh.names[0]}'" in bad.attrs["diagnosis"]
    assert f"module of {module * 1e3:.3g} mm" in bad.attrs["diagnosis"]


def test_planetary_overload_deflection_suspect(examples_dir):
    """lin_parker with 1000 × its carrier torque (9.6e4 N·m, applied at t = 0): the step passes
    the checks, but the meshes deflect beyond 0.1 module (module 2 mm → 0.2 mm), so the run
    ends 'suspect' with its result. Hand bound: each planet's sun and ring meshes share the
    carrier force equally (planet moment balance), F = T / (6 r_c) = 9.6e4 / 0.36 = 2.7e5 N,
    δ = F / k̄ = 0.53 mm statically (k̄ = 5e8 N/m); a load applied at once overshoots at most to
    twice that, ±10 % for the stiffness variation and the line-of-action angles: 0.45-1.3 mm."""
    cfg = load_config(examples_dir / "planetary_lin_parker.toml")
    d = cfg.model_dump(exclude_none=True)
    d["planetary_dynamics"]["simulation"]["torques"][0]["torque_nm"] = -9.6e4
    ds = run_simulation(parse_config(d))
    assert ds.attrs["status"] == "suspect"
    assert "for a module of 2 mm (more than 0.1 × module)" in ds.attrs["diagnosis"]
    peak = float(np.abs(ds["mesh_deflection"].values).max())
    assert 0.45e-3 < peak < 1.3e-3
    assert ds.sizes["time"] == round(0.01 / 2e-5) + 1
