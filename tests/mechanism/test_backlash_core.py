"""Backlash and back-flank contact of the lumped models' meshes (issue 12): the variable springs
of solve/integrate.py and solve/lowrank.py, and the ``[dynamics]`` wiring.

Force law on the deflection δ (drive flank δ > 0) with backlash b: F = k δ for δ ≥ 0, 0 for
−b < δ < 0, k (δ + b) for δ ≤ −b (the piecewise-linear clearance oscillator of Kahraman & Singh,
J. Sound Vib. 142 (1990), seed 004 §2.2 ref. 9).

Closed form used (free, undamped, two inertias m₁, m₂ on one mesh, relative coordinate δ =
u₁ − u₂, effective mass m_e = m₁m₂/(m₁ + m₂), ω = √(k/m_e)): starting at δ = 0 with δ̇ = v₀ > 0
the teeth stay in drive-flank contact for half a period, δ = (v₀/ω) sin ωt, and leave at
t₁ = π/ω with δ̇ = −v₀; in flight δ̇ is constant (no force), so the back flank is met at
t₂ = t₁ + b/v₀; by the same argument it is left at t₃ = t₂ + π/ω with δ̇ = +v₀ and the drive
flank is met again at T = t₃ + b/v₀. Period T = 2π/ω + 2b/v₀ (the gap 2b is crossed twice
at speed v₀ per period, the two contacts each last π/ω).
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError, InputError
from geardyn.models.core.simulate import prepare, simulate
from geardyn.solve.integrate import (
    Drives,
    LinearSystem,
    VarSprings,
    adaptive,
    newmark,
    reference_rhs,
)
from geardyn.solve.lowrank import newmark_lowrank
from geardyn.solve.sanity import energy_residual

M1, M2, K, B, V0 = 2.0, 3.0, 1e7, 50e-6, 0.1  # kg, kg, N/m, m, m/s
M_E = M1 * M2 / (M1 + M2)
OMEGA = math.sqrt(K / M_E)
T_CONTACT = 2 * math.pi / OMEGA
PERIOD = T_CONTACT + 2 * B / V0


def _pair(backlash: float = B) -> LinearSystem:
    """Two inertias (u = r θ coordinates, kg) on one constant-stiffness mesh, no damping."""
    s = VarSprings.build([{"a": [1.0, -1.0], "b": [0.0, 0.0], "k": [K], "backlash": backlash}],
                         2)
    return LinearSystem(np.diag([M1, M2]), np.zeros((2, 2)), np.zeros((2, 2)), s,
                        Drives.build([]), np.zeros(0), np.zeros((0, 2)))


def _exact_events(periods: int) -> dict[str, np.ndarray]:
    """Closed-form separation and impact times (module docstring)."""
    n = np.arange(periods)
    t1 = math.pi / OMEGA
    return {"drive_separation": t1 + n * PERIOD, "back_impact": t1 + B / V0 + n * PERIOD,
            "back_separation": 2 * t1 + B / V0 + n * PERIOD, "drive_impact": (n + 1) * PERIOD}


def _crossings(t: np.ndarray, d: np.ndarray) -> dict[str, np.ndarray]:
    """Times (linear interpolation) at which δ(t) crosses 0 and −b, by direction."""
    out = {}
    for name, level, sense in (("drive_separation", 0.0, -1), ("back_impact", -B, -1),
                               ("back_separation", -B, 1), ("drive_impact", 0.0, 1)):
        x = d - level
        i = np.flatnonzero((x[:-1] * x[1:] < 0) & (np.sign(x[1:] - x[:-1]) == sense))
        out[name] = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return out


def _event_errors(t: np.ndarray, d: np.ndarray, periods: int) -> float:
    """Largest |t_sim − t_exact| / T over the first ``periods`` periods' four events."""
    got, ref = _crossings(t, d), _exact_events(periods)
    worst = 0.0
    for name, tr in ref.items():
        assert len(got[name]) >= periods, name
        worst = max(worst, float(np.abs(got[name][:periods] - tr).max()) / PERIOD)
    return worst


def test_free_vibration_with_clearance_closed_form() -> None:
    """Newmark (T_contact/400 and /200) against the closed-form impact and separation times
    over three periods: error 4.2e-5 T and 1.7e-4 T, second order in Δt (ratio ≥ 3.5 for a
    halved step; tolerance 1e-4 T at /400). The undamped motion keeps its energy: kinetic +
    contact energy at the end within 1e-4 of ½m₁v₀² (measured 3.4e-5 after 12 contact changes:
    each changes the energy by O((ωΔt)²) since the contact state is taken at the step's
    predictor; the run's balance books it as parametric work and closes to 1e-8)."""
    s = _pair()
    errs = []
    for per_contact in (200, 400):
        r = newmark(s, np.zeros(2), np.array([V0, 0.0]), 3.2 * PERIOD,
                    T_CONTACT / per_contact)
        assert r.status == "ok"
        errs.append(_event_errors(r.t, r.delta[:, 0], 3))
    assert errs[1] < 1e-4
    assert errs[0] / errs[1] > 3.5
    e0 = 0.5 * M1 * V0**2
    e1 = r.energy["kinetic_end_J"] + r.energy["potential_end_J"]
    assert abs(e1 - e0) < 1e-4 * e0
    res, scale = energy_residual(r.energy)
    assert abs(res) < 1e-8 * scale


def test_free_vibration_with_clearance_solve_ivp() -> None:
    """The same system with scipy's solve_ivp: the plain-numpy right-hand side (DOP853,
    events at δ = 0 and δ = −b) within 1e-8 T of the closed form, and the compiled
    right-hand side (:func:`adaptive`, LSODA, rtol 1e-10) within 1e-7 T."""
    s = _pair()
    events = [lambda t, y, lev=lev: y[0] - y[1] - lev for lev in (0.0, -B)]
    sol = solve_ivp(reference_rhs(s), (0.0, 3.2 * PERIOD), [0.0, 0.0, V0, 0.0],
                    method="DOP853", rtol=1e-11, atol=1e-14, events=events,
                    max_step=PERIOD / 50)
    ref = _exact_events(3)
    at0, atb = sol.t_events[0], sol.t_events[1]
    # δ = 0 at t = 0, then drive separation, drive impact, ...; δ = −b: back impact, separation
    assert at0[1:7:2] == pytest.approx(ref["drive_separation"], abs=1e-8 * PERIOD)
    assert at0[2:8:2] == pytest.approx(ref["drive_impact"], abs=1e-8 * PERIOD)
    assert atb[0:6:2] == pytest.approx(ref["back_impact"], abs=1e-8 * PERIOD)
    assert atb[1:6:2] == pytest.approx(ref["back_separation"], abs=1e-8 * PERIOD)
    t_eval = np.linspace(0.0, 3.2 * PERIOD, 4001)
    ra = adaptive(s, np.zeros(2), np.array([V0, 0.0]), t_eval, rtol=1e-10, atol=1e-14)
    assert ra.status == "ok"
    assert _event_errors(ra.t, ra.q[:, 0] - ra.q[:, 1], 3) < 1e-7


# ---- three inertias, two meshes with backlash, excited near resonance -----------------------

M3 = np.array([2.0, 3.0, 4.0])  # kg (u coordinates)
K1, K2, B1, B2 = 1e7, 2e7, 50e-6, 30e-6  # N/m, m
E_AMP, PITCH, F0 = 20e-6, 0.01, 50.0  # m, m (base pitch), N
V_RIGID = 3.1431799  # m/s: mesh 1's frequency V/p_b = 0.9 × the highest natural frequency


def _chain(mirror: bool = False, damping: float = 0.0) -> LinearSystem:
    """1 –mesh 1– 2 –mesh 2– 3; mesh 1 with a sinusoidal error e(X), X = u₁/p_b + x₀ (64
    samples per cycle); mesh 2 with a two-sample stiffness table at a fixed phase; a light
    preload +F₀ on 1 and −F₀ on 3. ``mirror``: load and errors reversed and the errors shifted
    by −b (e' (Y) = −e(−Y) − b, x₀ → −x₀), the system whose response is −q."""
    sg = -1.0 if mirror else 1.0
    x = np.arange(64) / 64
    e1 = E_AMP * np.sin(2 * np.pi * x) - (B1 if mirror else 0.0)
    rows = [{"a": [1.0, -1.0, 0.0], "b": [1 / PITCH, 0.0, 0.0], "x0": 0.1 * sg, "k": [K1],
             "e": e1, "c": damping, "backlash": B1},
            {"a": [0.0, 1.0, -1.0], "b": [0.0, 0.0, 0.0], "k": [K2, 0.8 * K2],
             "e": [-B2 if mirror else 0.0], "c": damping, "backlash": B2}]
    force = sg * np.array([[F0, 0.0, -F0], [F0, 0.0, -F0]])
    return LinearSystem(np.diag(M3), np.zeros((3, 3)), np.zeros((3, 3)),
                        VarSprings.build(rows, 3), Drives.build([]), np.array([0.0, 1.0]), force)


DT3 = 1 / 595.889 / 400  # s: 400 steps per shortest natural period
V3 = np.full(3, V_RIGID)


@pytest.fixture(scope="module")
def chain_run():
    return newmark(_chain(), np.zeros(3), V3, 0.05, DT3, solve="dense")


def _law(d: np.ndarray, k: float, b: float) -> np.ndarray:
    return np.where(d >= 0, k * d, np.where(d > -b, 0.0, k * (d + b)))


def test_double_sided_impacts_force_law_and_energy(chain_run) -> None:
    """Both meshes reach both flanks (each state ≥ 15 % of the samples); the recorded force
    k·δ is the contact law of the recorded deflection (1e-12 of the largest force; back flank
    negative); without damping the energy balance closes (applied + parametric work of the
    error = Δ(kinetic + contact energy), 1e-6 of the energy exchanged, measured 1.7e-7) and the
    momentum Σ m v is kept (the mesh forces are internal, the preload sums to zero: 1e-12)."""
    r = chain_run
    assert r.status == "ok"
    f = r.k * r.delta
    for e, (k, b) in enumerate(((K1, B1), (K2, B2))):
        d = r.delta[:, e]
        n = len(d)
        assert (d <= -b).sum() > 0.15 * n and (d >= 0).sum() > 0.15 * n
        assert ((d > -b) & (d < 0)).sum() > 0.15 * n
        kk = k if e == 0 else r.k[:, e].max()  # mesh 2 sits on its first sample, k = K2
        assert kk == pytest.approx(K2 if e else K1, rel=1e-15)
        assert np.abs(f[:, e] - _law(d, kk, b)).max() < 1e-12 * np.abs(f[:, e]).max()
        assert f[d <= -b, e].max() <= 0.0 < f[d > 0, e].min()
    res, scale = energy_residual(r.energy)
    assert r.energy["dissipated_J"] == 0.0
    assert abs(res) < 1e-6 * scale
    p = r.v @ M3
    assert np.abs(p - p[0]).max() < 1e-12 * abs(p[0])


def test_double_sided_impacts_solve_ivp(chain_run) -> None:
    """The first 10 ms (≈ 30 impacts per mesh) against solve_ivp (DOP853, rtol 1e-10) on the
    plain-numpy right-hand side: mesh deflections within 1e-3 of their range (measured
    3.7e-4; the Newmark step is Δt = T_min/400); the compiled right-hand side with LSODA
    within 1e-5 of the DOP853 solution (measured 1.3e-6)."""
    s = _chain()
    keep = chain_run.t <= 0.01
    te = chain_run.t[keep]
    sol = solve_ivp(reference_rhs(s), (0.0, te[-1]), np.concatenate([np.zeros(3), V3]),
                    method="DOP853", rtol=1e-10, atol=1e-14, t_eval=te, max_step=5 * DT3)
    a = s.springs.a
    ref = sol.y[:3].T @ a.T
    scale = np.abs(ref).max()
    assert np.abs(chain_run.q[keep] @ a.T - ref).max() < 1e-3 * scale
    ra = adaptive(s, np.zeros(3), V3, te, rtol=1e-10, atol=1e-14)
    assert np.abs(ra.q @ a.T - ref).max() < 1e-5 * scale


def test_dense_and_woodbury_steps_agree_with_backlash(chain_run) -> None:
    """The Woodbury step (newmark solve='lowrank', and solve/lowrank.py's newmark_lowrank)
    gives the dense step's run with impacts on both flanks: q and the mesh forces within
    1e-9 of their largest value (the same scheme; only the linear solve differs)."""
    ref = chain_run
    fr = ref.k * ref.delta
    for got in (newmark(_chain(), np.zeros(3), V3, 0.05, DT3, solve="lowrank"),
                newmark_lowrank(_chain(), np.zeros(3), V3, 0.05, DT3)):
        assert got.status == "ok"
        assert np.abs(got.q - ref.q).max() < 1e-9 * np.abs(ref.q).max()
        assert np.abs(got.k * got.delta - fr).max() < 1e-9 * np.abs(fr).max()


def test_mirror_symmetry(chain_run) -> None:
    """Load and error reversed, errors shifted by −b (the law is odd about δ = −b/2:
    F(−δ − b) = −F(δ)), initial state reversed: q → −q, δ → −δ − b, F → −F (1e-12)."""
    r = chain_run
    m = newmark(_chain(mirror=True), np.zeros(3), -V3, 0.05, DT3, solve="dense")
    assert np.abs(m.q + r.q).max() < 1e-12 * np.abs(r.q).max()
    assert np.abs(m.delta + r.delta + np.array([B1, B2])).max() < 1e-12 * B1
    f = r.k * r.delta
    assert np.abs(m.k * m.delta + f).max() < 1e-12 * np.abs(f).max()


def test_damping_acts_only_in_contact() -> None:
    """Mesh damping c along the line of action only while the teeth touch: the free pair with
    damping keeps its relative speed across the gap (flight time b/v exactly as the speed at
    separation gives it, 1e-3) and the dissipated work is booked (balance 1e-5, measured
    2.8e-6)."""
    c = 2 * 0.05 * math.sqrt(K * M_E)  # ζ = 0.05
    s = _pair()
    s.springs.c[:] = c
    r = newmark(s, np.zeros(2), np.array([V0, 0.0]), 1.2 * PERIOD, T_CONTACT / 1000)
    d = r.q[:, 0] - r.q[:, 1]
    w = r.v[:, 0] - r.v[:, 1]
    flight = (d < -1e-9) & (d > -B + 1e-9)
    assert flight.sum() > 50
    first = flight & (r.t < T_CONTACT)  # the first flight, drive to back flank
    assert np.ptp(w[first]) < 1e-12 * V0  # no force at all in flight
    cr = _crossings(r.t, r.delta[:, 0])
    t_gap = cr["back_impact"][0] - cr["drive_separation"][0]
    assert t_gap == pytest.approx(B / abs(w[first][0]), rel=1e-3)
    assert abs(w[first][0]) < V0  # damped in the first contact
    res, scale = energy_residual(r.energy)
    assert r.energy["dissipated_J"] > 0 and abs(res) < 1e-5 * scale


# ---- b = 0: the previous law, unchanged ----------------------------------------------------


def _guard_system(**extra: object) -> LinearSystem:
    """3 inertias, a two-sided mesh (stiffness and error tables) and a one-sided one (contact
    loss), a speed control on DOF 0 and a torque on DOF 2."""
    x = np.arange(8) / 8
    springs = VarSprings.build([
        {"a": [1.0, -1.0, 0.0], "b": [50.0, 0.0, 0.0], "k": 1e7 * (1 + 0.3 * (x < 0.4)),
         "e": 5e-6 * np.sin(2 * np.pi * x), "c": 30.0, **extra},
        {"a": [0.0, 1.0, -1.0], "b": [0.0, 50.0, 0.0], "x0": 0.3, "k": [2e7, 1.5e7],
         "e": [2e-6, -4e-6, 1e-6], "c": 20.0, "contact_loss": True, **extra},
    ], 3)
    drives = Drives.build([{"kind": 3, "a": 0, "p0": 1e5, "p1": 500.0, "x": [0.0, 1.0],
                            "y": [0.0, 2.0]}])
    force = np.array([[0.0, 0.0, -40.0], [0.0, 0.0, -40.0]])
    return LinearSystem(np.diag([2.0, 3.0, 4.0]), np.zeros((3, 3)), np.zeros((3, 3)), springs,
                        drives, np.array([0.0, 1.0]), force)


@pytest.mark.parametrize("solve", ["dense", "lowrank"])
def test_zero_backlash_keeps_the_previous_results(solve) -> None:
    """Regression guard (values pinned from the solver before backlash existed, commit
    5b7c866, on this machine bit-identical; 1e-12 here): the two-sided law and the one-sided
    contact-loss law (89 of the 2501 samples separated) with HHT α = 0.05. ``backlash = 0``
    given explicitly gives the same arrays as no backlash at all."""
    r = newmark(_guard_system(), np.zeros(3), np.full(3, 2.0), 0.05, 2e-5, alpha=0.05,
                solve=solve)
    f = r.k * r.delta
    assert (r.k[:, 1] == 0).sum() == 89
    got = [r.q[-1, 0] - r.q[-1, 1], r.q[-1, 1] - r.q[-1, 2], f[:, 0].sum(), f[:, 1].sum(),
           f.max(), r.energy["kinetic_end_J"], r.energy["potential_end_J"],
           r.energy["parametric_J"], r.energy["dissipated_J"]]
    pinned = [3.110768324959823e-06, 5.777215097022004e-06, 104021.66451112306,
              102202.37197558655, 73.31397164185611, 18.184174946524344,
              0.00010518309007397956, 7.794426384257879e-05, 2.872314560528614e-05]
    assert got == pytest.approx(pinned, rel=1e-12)
    z = newmark(_guard_system(backlash=0.0), np.zeros(3), np.full(3, 2.0), 0.05, 2e-5,
                alpha=0.05, solve=solve)
    for a, b in ((z.q, r.q), (z.v, r.v), (z.k, r.k), (z.delta, r.delta)):
        assert np.array_equal(a, b)


def test_bad_backlash_is_an_input_error() -> None:
    for bad in (-1e-6, float("nan"), float("inf")):
        with pytest.raises(InputError, match="backlash of variable spring #0"):
            _pair(bad)


# ---- [dynamics] wiring -----------------------------------------------------------------------


def _differential(examples_dir, **mesh: object) -> dict:
    d = tomllib.loads((examples_dir / "car_differential_dynamics.toml").read_text())
    d["dynamics"]["meshes"][0].update(mesh)
    d["dynamics"]["simulation"].update(save_every=1)
    d["dynamics"]["simulation"]["torques"][0]["torque_nm"] = -5.0
    return d


def test_dynamics_backlash_config(examples_dir) -> None:
    """``[[dynamics.meshes]] backlash_m`` with a unit reaches its mesh only; a negative or
    non-finite value is a ConfigError naming the field."""
    p = prepare(parse_config(_differential(examples_dir, backlash_m="60 um")), 0.01)
    names = [m.name for m in p.model.meshes]
    want = [60e-6 if n == "2-7" else 0.0 for n in names]
    assert p.system.springs.backlash == pytest.approx(want, rel=1e-12)
    for bad in (-1e-5, "-0.1 mm", float("nan")):
        with pytest.raises(ConfigError, match=r"dynamics\.meshes\[0\]\.backlash_m"):
            parse_config(_differential(examples_dir, backlash_m=bad))


def test_dynamics_run_with_backlash(examples_dir) -> None:
    """The car differential under a light load (5 N·m) with a 20 µm transmission error on the
    crown pair and 60 µm backlash: the crown pair reaches its back flank, the recorded force is
    the contact law, the run's energy balance closes within 2e-3 (status ok; measured 7e-6);
    the dense and Woodbury Newmark steps give the same run (1e-9), solver 'lowrank'
    (solve/lowrank.py: sparse LU, restarts) within 1e-7 (measured 1.8e-8)."""
    d0 = _differential(examples_dir, backlash_m=60e-6, transmission_error_m=20e-6)
    cfg = parse_config(d0)
    ds = simulate(cfg, 0.05)
    assert ds.attrs["status"] == "ok"
    en = {k[len("energy_"):]: v for k, v in ds.attrs.items() if k.startswith("energy_")}
    res, scale = energy_residual(en)
    assert abs(res) < 2e-3 * scale
    d = ds["mesh_deflection"].sel(mesh="2-7").values
    f = ds["mesh_force"].sel(mesh="2-7").values
    back, gap = d <= -60e-6, (d > -60e-6) & (d < 0)
    assert back.sum() >= 10
    assert np.all(f[back] < 0) and np.all(f[gap] == 0) and np.all(f[d > 0] > 0)
    # |F| / contact compression is a value of the square-wave stiffness table
    p = prepare(cfg, 0.05)
    k = p.system.springs.ktab[[m.name for m in p.model.meshes].index("2-7")]
    on = ~gap & (d != 0)
    ratio = np.abs(f[on]) / np.abs(np.where(back, d + 60e-6, d)[on])
    assert ratio.min() > k.min() * (1 - 1e-9) and ratio.max() < k.max() * (1 + 1e-9)
    dense = newmark(p.system, p.q0, p.v0, 0.05, p.sim.dt_s, solve="dense")
    wood = newmark(p.system, p.q0, p.v0, 0.05, p.sim.dt_s, solve="lowrank")
    fd, fw = dense.k * dense.delta, wood.k * wood.delta
    assert np.abs(fw - fd).max() < 1e-9 * np.abs(fd).max()
    assert np.abs(fd - ds["mesh_force"].values).max() < 1e-9 * np.abs(fd).max()
    d0["dynamics"]["simulation"]["solver"] = "lowrank"
    lr = simulate(parse_config(d0), 0.05)
    fl = lr["mesh_force"].values
    assert np.abs(fl - fd).max() < 1e-7 * np.abs(fd).max()  # as tests/mechanism/test_lowrank


def test_compiled_and_numpy_right_hand_sides_agree() -> None:
    """The compiled right-hand side (kernels) and the plain-numpy one (written from the law)
    at 300 random states spread over drive flank, gap and back flank of both meshes (1e-12 of
    the largest acceleration)."""
    from geardyn.solve.integrate import compiled_rhs

    s = _chain(damping=40.0)
    f, g = compiled_rhs(s), reference_rhs(s)
    rng = np.random.default_rng(12)
    states = {0: 0, 1: 0, -1: 0}
    for _ in range(300):
        y = np.concatenate([rng.uniform(-3 * B1, 3 * B1, 3), rng.uniform(-1, 1, 3)])
        d = s.springs.a @ y[:3]
        for dd, b in zip(d, (B1, B2), strict=True):
            states[1 if dd >= 0 else 0 if dd > -b else -1] += 1
        t = rng.uniform(0, 1)
        a, r = f(t, y), g(t, y)
        assert np.abs(a - r).max() <= 1e-12 * np.abs(r).max()
    assert min(states.values()) > 50


def test_chunked_run_is_identical_with_backlash(chain_run) -> None:
    """Runs cut into chunks (progress, stop requests, checkpoints) continue exactly: 97-step
    chunks give the same arrays and energy terms as one piece."""
    r = newmark(_chain(), np.zeros(3), V3, 0.05, DT3, solve="dense", chunk_steps=97)
    for a, b in ((r.q, chain_run.q), (r.v, chain_run.v), (r.k, chain_run.k),
                 (r.delta, chain_run.delta)):
        assert np.array_equal(a, b)
    assert r.energy == chain_run.energy
