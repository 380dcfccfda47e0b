"""Time integration: energy conservation, agreement with solve_ivp, kernels vs the plain-numpy
right-hand side, HHT dissipation, divergence diagnosis."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from geardyn.config.loader import load_config
from geardyn.models.planetary.build import prepare
from geardyn.models.planetary.dynamics import MeshLaw, build_system
from geardyn.solve.integrate import compiled_rhs, newmark, reference_rhs

from .conftest import EX


def _energy(sys, q, v):
    k = _k_total(sys)
    return 0.5 * np.einsum("ti,ij,tj->t", v, sys.M, v) + 0.5 * np.einsum("ti,ij,tj->t", q, k, q)


def _k_total(sys):
    k = sys.K.copy()
    for e in range(sys.springs.a.shape[0]):
        k += sys.springs.ktab[e, 0] * np.outer(sys.springs.a[e], sys.springs.a[e])
    return k


def test_energy_conserved_undamped_constant_stiffness(lin_parker):
    """Average-acceleration Newmark conserves ½vᵀMv + ½qᵀKq exactly for a linear undamped
    system (constant mesh stiffness kept as variable springs to exercise the kernel)."""
    laws = {("stage", "sun"): MeshLaw.constant(5e8), ("stage", "ring"): MeshLaw.constant(5e8)}
    sys, _ = build_system(lin_parker, laws)
    rng = np.random.default_rng(1)
    n = sys.n
    q0 = rng.normal(size=n) * 1e-6
    v0 = rng.normal(size=n) * 1e-3
    res = newmark(sys, q0, v0, t_end=0.02, dt=1e-5)
    assert res.status == "ok"
    e = _energy(sys, res.q, res.v)
    assert np.ptp(e) / e[0] < 1e-10
    # HHT-α dissipates the high modes: energy decreases
    res2 = newmark(sys, q0, v0, t_end=0.02, dt=1e-5, alpha=0.1)
    e2 = _energy(sys, res2.q, res2.v)
    assert e2[-1] < 0.9 * e2[0]


def test_kernels_match_plain_numpy_rhs():
    """The compiled right-hand side equals the independent numpy one (time-varying meshes,
    errors, crack tables, motor, fluid coupling, load, gyroscopic terms) at random states."""
    import tomllib

    from geardyn.config.loader import parse_config

    with open(EX / "planetary_reclaimer.toml", "rb") as fh:
        d = tomllib.load(fh)
    d["planetary_dynamics"]["simulation"]["gyroscopic"] = True
    d["planetary_dynamics"]["simulation"]["modal_damping_ratio"] = 0.02
    p = prepare(parse_config(d))
    assert p.system.gyro_g.shape[0] == 1
    f_c = compiled_rhs(p.system)
    f_p = reference_rhs(p.system)
    rng = np.random.default_rng(0)
    for _ in range(5):
        y = np.concatenate([p.q0 + rng.normal(size=p.system.n) * 1e-5,
                            p.v0 + rng.normal(size=p.system.n) * 1e-3])
        y[: p.system.n] += rng.uniform(0, 3) * p.v0  # arbitrary mesh positions
        t = rng.uniform(0, 0.05)
        a, b = f_c(t, y), f_p(t, y)
        np.testing.assert_allclose(a, b, rtol=1e-7, atol=1e-9 * np.abs(b).max())


def test_newmark_agrees_with_solve_ivp_time_varying():
    """Short run of the Lin & Parker example (angle-dependent sine mesh stiffness, speed
    control, load): Newmark vs solve_ivp (DOP853, rtol 1e-10) on the same compiled RHS.
    Tolerance: 1e-3 of the mesh-deflection range and 1e-6 relative on the rotation."""
    cfg = load_config(EX / "planetary_lin_parker.toml")
    p = prepare(cfg)
    t_end, dt = 2e-3, 2.5e-7
    res = newmark(p.system, p.q0, p.v0, t_end, dt, save_every=400)
    sol = solve_ivp(compiled_rhs(p.system), (0, t_end), np.concatenate([p.q0, p.v0]),
                    method="DOP853", rtol=1e-10, atol=1e-14, t_eval=res.t)
    n = p.system.n
    a = p.system.springs.a
    d_nm = res.q @ a.T
    d_ivp = sol.y[:n].T @ a.T
    scale = np.ptp(d_ivp, axis=0).max()
    assert np.abs(d_nm - d_ivp).max() < 1e-3 * scale
    i = p.model.dof("sun.u")
    np.testing.assert_allclose(res.q[-1, i], sol.y[i, -1], rtol=1e-6)


def test_divergence_stops_and_keeps_results(lin_parker):
    """A negative stiffness (unstable) run stops with a diagnosis naming the DOF and time and
    keeps the steps computed before."""
    sys, _ = build_system(lin_parker, {})
    j = lin_parker.dof("carrier.x")
    sys.K[j, j] = -1e9
    q0 = np.zeros(sys.n)
    q0[j] = 1e-9
    res = newmark(sys, q0, np.zeros(sys.n), t_end=0.1, dt=1e-5, q_limit=1.0)
    assert res.status == "diverged"
    assert "carrier.x" in res.diagnosis and "t =" in res.diagnosis
    assert 1 < len(res.t) < 10001
    assert np.all(np.isfinite(res.q))
    assert np.abs(res.q[-1, j]) <= 1.0


def test_adaptive_option_agrees_with_newmark():
    cfg = load_config(EX / "planetary_lin_parker.toml")
    p = prepare(cfg)
    from geardyn.solve.integrate import adaptive

    res = newmark(p.system, p.q0, p.v0, 1e-3, 2.5e-7, save_every=400)
    ad = adaptive(p.system, p.q0, p.v0, res.t, rtol=1e-9, atol=1e-14)
    assert ad.status == "ok"
    a = p.system.springs.a
    d_nm, d_ad = res.q @ a.T, ad.q @ a.T
    assert np.abs(d_nm - d_ad).max() < 2e-3 * np.ptp(d_ad, axis=0).max()


def test_pin_errors_in_simulation_shift_load_sharing():
    """Config ``pin_errors_m`` (seed 003 ch. 5) in a damped run of the Lin & Parker stage:
    the planet with the positive error carries more than 1/N, the negative one less."""
    import copy
    import tomllib

    from geardyn.config.loader import parse_config
    from geardyn.models.planetary.dynamics import simulate

    with open(EX / "planetary_lin_parker.toml", "rb") as fh:
        d = tomllib.load(fh)
    d = copy.deepcopy(d)
    d["planetary_dynamics"]["stages"][0]["pin_errors_m"] = [2e-6, 0.0, -2e-6, 0.0]
    d["planetary_dynamics"]["stages"][0]["sun_mesh"]["amplitude"] = 0.0
    d["planetary_dynamics"]["stages"][0]["ring_mesh"]["amplitude"] = 0.0
    d["planetary_dynamics"]["simulation"]["rayleigh_beta"] = 2e-5
    p = prepare(parse_config(d))
    ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, 0.01, 2e-5)
    lsr = ds.lsr_stage.isel(time=slice(-100, None)).mean("time").values
    assert lsr.sum() == pytest.approx(1.0, rel=1e-6)
    assert lsr[0] > 0.25 > lsr[2]
    assert lsr[1] == pytest.approx(lsr[3], rel=1e-3)


def test_modal_damping_ratio_recovered(lin_parker):
    """C = MΦ diag(2ζω)ΦᵀM: the damped eigenvalues have ζ = −Re λ/|λ| on every elastic mode."""
    from geardyn.models.planetary.modal import modes

    sys, _ = build_system(lin_parker, {}, modal_damping=0.03)
    n = sys.n
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    minv = np.linalg.inv(sys.M)
    a[n:, :n] = -minv @ sys.K
    a[n:, n:] = -minv @ sys.C
    lam = np.linalg.eigvals(a)
    lam = lam[np.abs(lam) > 2 * np.pi * 1.0]
    zeta = -lam.real / np.abs(lam)
    np.testing.assert_allclose(zeta, 0.03, rtol=1e-6)
    f = np.sort(np.abs(lam[lam.imag > 0]) / (2 * np.pi))
    np.testing.assert_allclose(f, np.sort(modes(lin_parker).freq_hz[1:]), rtol=1e-6)
