"""Gyroscopic terms and applied loads (unbalance, external forces) of the FE time integration
(issue 12), against closed forms: the spinning rigid disc on tilt springs (Lalanne & Ferraris,
*Rotordynamics Prediction in Engineering*, 1998, ch. 2: I_d r̈ − i I_p Ω ṙ + k r = 0), the Jeffcott
unbalance response x = m e Ω² / (k − M Ω² + i c Ω) (Friswell et al., *Dynamics of Rotating
Machines*, 2010, ch. 3), the static deflection F/k, and energy balances."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.config.loader import load_config, parse_config
from geardyn.elements.disc import disc_gyroscopic, rigid_disc
from geardyn.errors import ConfigError
from geardyn.models.transmission.assembly import build_model
from geardyn.models.transmission.integrate import (
    E_EXT,
    E_MODAL,
    gyroscopic_args,
    gyroscopic_forces,
    no_loads,
    run_loop,
)
from geardyn.models.transmission.simulate import simulate
from tests.transmission._empty import empty_bearings, empty_meshes

# one rigid disc (node 0): m = 10 kg, I_p = 0.2 kg·m², I_d = 0.1 kg·m²
MASS, IP, ID = 10.0, 0.2, 0.1


def _disc_run(K, C, q0, v0, dt, n_steps, rec_dofs, gyro: bool, xargs=None):
    """Integrate the one-disc model with :func:`run_loop` (no drive, no load)."""
    M = rigid_disc(MASS, IP, ID)
    gargs = gyroscopic_args({"s": disc_gyroscopic(IP)}, {"s": [5]}) if gyro else None
    rec, energy, done, status, q, v, _ = run_loop(
        q0.copy(), v0.copy(), dt, n_steps, 1, np.linalg.inv(M), K, C, empty_bearings(),
        empty_meshes(), 5, 5, 5, 1.0, 1.0, 1.0, 0.0, np.array([0.0, 1e9]), np.array([0.0, 0.0]),
        0.0, 0.0, 0.0, 0.0, 1.0, np.asarray(rec_dofs, np.int64), gargs=gargs, xargs=xargs)
    assert status == 0 and done == n_steps
    return rec, energy, q, v


def test_spinning_disc_whirl_matches_closed_form() -> None:
    """Tilt impulse on a disc spinning at Ω = 300 rad/s on tilt springs k = 4e4 N·m/rad:
    r = θx + iθy = ṙ₀ (e^{iλ_f t} − e^{iλ_b t}) / (i(λ_f − λ_b)), λ = (I_pΩ ± √(I_p²Ω² +
    4 I_d k)) / 2I_d (forward 1000, backward −400 rad/s). Magnitude and phase of
    the time history within 0.2 % of the amplitude over 40 whirl periods; the tilt energy
    (gyroscopic forces do no work) constant within 1e-5."""
    k, om, w0 = 4.0e4, 300.0, 1e-3
    K = np.diag([1e6, 1e6, 1e6, k, k, 0.0])
    v0 = np.array([0, 0, 0, w0, 0, om], float)
    lf = (IP * om + math.sqrt((IP * om) ** 2 + 4 * ID * k)) / (2 * ID)
    lb = (IP * om - math.sqrt((IP * om) ** 2 + 4 * ID * k)) / (2 * ID)
    dt = 2e-6
    n = int(40 * 2 * math.pi / lf / dt)
    rec, _, q, v = _disc_run(K, np.zeros((6, 6)), np.zeros(6), v0, dt, n, [3, 4], True)
    t = rec[:, 0]
    r_ref = w0 * (np.exp(1j * lf * t) - np.exp(1j * lb * t)) / (1j * (lf - lb))
    r = rec[:, 2] + 1j * rec[:, 3]
    amp = 2 * w0 / (lf - lb)
    assert np.max(np.abs(r - r_ref)) < 2e-3 * amp
    # without the gyroscopic terms the two whirls collapse onto √(k/I_d): the check can fail
    rec0, *_ = _disc_run(K, np.zeros((6, 6)), np.zeros(6), v0, dt, n, [3, 4], False)
    assert np.max(np.abs(rec0[:, 2] + 1j * rec0[:, 3] - r_ref)) > 0.3 * amp
    e_tilt = 0.5 * ID * (v[3] ** 2 + v[4] ** 2) + 0.5 * k * (q[3] ** 2 + q[4] ** 2)
    assert e_tilt == pytest.approx(0.5 * ID * w0 ** 2, rel=1e-5)
    assert v[5] == om  # the spin is untouched (G couples the tilts only)


def test_gyroscopic_args_reassemble_the_shaft_matrices(examples_dir) -> None:
    """The sparse loop form of Σ_s Ω_s G_s v equals the dense assembled matrices of the seed 002
    transmission (every shaft spinning at its own θ̇z)."""
    model = build_model(load_config(examples_dir / "seed002_transmission.toml"))
    spin = {s: [6 * nd + 5 for nd in ids] for s, ids in model.shaft_nodes.items()}
    ga = gyroscopic_args(model.gyroscopic, spin)
    rng = np.random.default_rng(1)
    v = rng.normal(size=model.ndof)
    om = {s: 10.0 * (i + 1) for i, s in enumerate(spin)}
    for s, dofs in spin.items():
        v[dofs] = om[s]
    f = np.zeros(model.ndof)
    gyroscopic_forces(v, f, *ga)
    ref = -sum(om[s] * g @ v for s, g in model.gyroscopic.items())
    assert np.allclose(f, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    assert np.abs(ref).max() > 0


def _unbalance_args(me: float, phase: float) -> tuple:
    z, zi = np.zeros(0), np.zeros(0, np.int64)
    return (np.array([0], np.int64), np.array([me]), np.array([phase]), zi, z, z, z, z, zi, z)


@pytest.mark.parametrize("ratio", [0.6, 1.0, 1.7])
def test_unbalance_response_matches_jeffcott(ratio: float) -> None:
    """Disc on lateral springs k = 1e6 N/m with damping ζ = 0.1, spinning at Ω = ratio × ω_n,
    unbalance m e = 1e-4 kg·m at 30°: steady x + iy = m e Ω² e^{i(Ωt + φ)} / (k − MΩ² + icΩ)
    (amplitude and phase within 0.5 % of the amplitude after the transient has decayed)."""
    k = 1.0e6
    wn = math.sqrt(k / MASS)
    c = 2 * 0.1 * math.sqrt(k * MASS)
    om = ratio * wn
    me, ph = 1e-4, math.radians(30.0)
    K = np.diag([k, k, 1e6, 1e4, 1e4, 0.0])
    C = np.diag([c, c, 0.0, 0.0, 0.0, 0.0])
    dt = 1e-5
    n = int(60 / (0.1 * wn) / dt)  # 60 decay time constants
    rec, *_ = _disc_run(K, C, np.zeros(6), np.array([0, 0, 0, 0, 0, om], float), dt, n,
                        [0, 1], False, _unbalance_args(me, ph))
    t = rec[:, 0]
    tail = t > t[-1] - 5 * 2 * math.pi / om
    z_ref = me * om ** 2 * np.exp(1j * (om * t[tail] + ph)) / (k - MASS * om ** 2 + 1j * c * om)
    z = rec[tail, 2] + 1j * rec[tail, 3]
    amp = abs(z_ref[0])
    assert np.max(np.abs(z - z_ref)) < 5e-3 * amp


def test_constant_force_static_deflection_and_work() -> None:
    """Constant force F = 500 N on y and torque 20 N·m about x of a damped disc: the rest state
    is F/k (1e-4 relative) and the external work = stored elastic energy + damping losses."""
    k, kt = 1.0e6, 1.0e4
    K = np.diag([k, k, 1e6, kt, kt, 0.0])
    C = np.diag([2 * 0.2 * math.sqrt(k * MASS)] * 3 + [2 * 0.2 * math.sqrt(kt * ID)] * 2 + [0.0])
    z, zi = np.zeros(0), np.zeros(0, np.int64)
    xargs = (zi, z, z, np.array([1, 3], np.int64), np.array([500.0, 20.0]), np.zeros(2),
             np.zeros(2), np.zeros(2), np.array([5, 5], np.int64), np.zeros(2))
    rec, energy, q, v = _disc_run(K, C, np.zeros(6), np.zeros(6), 1e-5, 40000, [1, 3], False,
                                  xargs)
    assert q[1] == pytest.approx(500.0 / k, rel=1e-4)
    assert q[3] == pytest.approx(20.0 / kt, rel=1e-4)
    stored = 0.5 * q @ K @ q + 0.5 * v @ rigid_disc(MASS, IP, ID) @ v
    assert energy[E_EXT] == pytest.approx(stored + energy[E_MODAL], rel=1e-4)
    assert no_loads()[0].size == 0


@pytest.fixture(scope="module")
def seed002(examples_dir) -> dict:
    return load_config(examples_dir / "seed002_transmission.toml").model_dump(exclude_none=True)


def test_seed002_unbalance_gyroscopic_housing_force_and_energy(seed002) -> None:
    """Seed 002 transmission at 400 rpm (output) with gyroscopic terms, an unbalance on the input
    wheel and a harmonic external torque on the output: far below the lateral criticals the two
    input bearings pass the rotating unbalance force m e Ω² to the housing (1× component of
    their summed housing force within 3 %, its phase the unbalance's 45° within 3°), and the
    energy balance including the work of the external loads closes within 1 %."""
    d = {**seed002, "transmission": {**seed002["transmission"]}}
    t = d["transmission"]
    t["speed_law"] = {**t["speed_law"], "start_rpm": 400.0, "end_rpm": 400.0}
    t["simulation"] = {**t.get("simulation", {}), "gyroscopic": True}
    wheel = next(w for w in t["wheels"] if w["at"]["shaft"] == "input")
    me = 1e-2
    t["unbalance"] = [{"at": wheel["at"], "mass_eccentricity_kg_m": me, "phase_deg": 45.0}]
    t["external_loads"] = [{"at": t["load"]["at"], "dof": "rz", "amplitude": 5.0, "order": 3.0}]
    cfg = parse_config(d)
    ds = simulate(cfg, revolutions=3.0)
    a = ds.attrs
    assert a["status"] == "ok", a.get("diagnosis")
    assert abs(a["energy_external_loads_J"]) > 0
    ein, eout = a["energy_input_J"], a["energy_output_J"]
    diss = sum(a[f"energy_{k}_J"] for k in ("bearing_viscous", "rolling_resistance",
                                          "gear_friction", "squeeze_film", "modal_damping"))
    dst = a["energy_stored_end_J"] - a["energy_stored_start_J"]
    assert abs(ein - eout + a["energy_external_loads_J"] - diss - dst) < 0.01 * ein
    # 1× of the input shaft in the summed housing force of its bearings, over whole revolutions
    sgn = build_model(cfg).shaft_sign["input"]  # θz = sgn × the recorded angle
    names = [b["name"] for b in t["bearings"] if b["at"]["shaft"] == "input"]
    assert len(names) == 2
    fh = ds.bearing_force.sel(bearing=names).sum("bearing")
    keep = ds.time.values > ds.time.values[-1] / 3
    ang = ds.angle.sel(shaft="input").values[keep]
    w = ds.speed.sel(shaft="input").values[keep]
    z = (fh.sel(axis="x").values + 1j * fh.sel(axis="y").values)[keep]
    whole = np.abs(ang - ang[0]) < 2 * math.pi * math.floor(abs(ang[-1] - ang[0]) / (2 * math.pi))
    z = z[whole] - z[whole].mean()
    one_x = np.mean(z * np.exp(-1j * sgn * ang[whole]))
    expected = me * np.mean(w[whole] ** 2)
    assert abs(one_x) == pytest.approx(expected, rel=0.03)
    assert math.degrees(np.angle(one_x)) == pytest.approx(45.0, abs=3.0)  # the unbalance phase


def test_load_fields_are_checked(seed002) -> None:
    d = {**seed002, "transmission": {**seed002["transmission"]}}
    d["transmission"]["unbalance"] = [{"at": {"shaft": "nope", "node": 0},
                                       "mass_eccentricity_kg_m": 1e-3}]
    with pytest.raises(ConfigError, match=r"unbalance\[0\]\.at\.shaft"):
        parse_config(d)
    d["transmission"]["unbalance"] = [{"at": {"shaft": "input", "node": 0},
                                       "mass_eccentricity_kg_m": -1.0}]
    with pytest.raises(ConfigError, match="mass_eccentricity_kg_m"):
        parse_config(d)
    d["transmission"]["unbalance"] = []
    d["transmission"]["external_loads"] = [{"at": {"shaft": "input", "node": 0}, "dof": "w"}]
    with pytest.raises(ConfigError, match="dof"):
        parse_config(d)


def test_overhung_rotor_free_whirl_matches_campbell() -> None:
    """Timoshenko shaft (Ø40 mm × 0.6 m, 12 elements) on two linear supports with an overhung
    disc, spinning at 600 rad/s: the spectrum of the disc's whirl r = x + iy after a lateral
    impulse peaks at the forward (> 0) and backward (< 0) whirl frequencies of the first mode
    pair given by the eigenvalues of M q̈ + Ω G q̇ + K q = 0 (the Campbell computation of
    :func:`geardyn.models.transmission.assembly.campbell`), within 0.1 %."""
    from geardyn.elements.beam import ShaftSection
    from geardyn.elements.beam import timoshenko_gyroscopic as tg
    from geardyn.models.transmission.assembly import assemble_shaft

    sec = ShaftSection(0.04)
    ne, length = 12, 0.6
    K, M = assemble_shaft(sec, length, ne)
    n = K.shape[0]
    G = np.zeros((n, n))
    ge = tg(length / ne, sec)
    for e in range(ne):
        G[6 * e : 6 * e + 12, 6 * e : 6 * e + 12] += ge
    d = 6 * ne
    M[d : d + 6, d : d + 6] += rigid_disc(MASS, IP, ID)
    G[d : d + 6, d : d + 6] += disc_gyroscopic(IP)
    for nd in (0, 8):
        K[6 * nd, 6 * nd] += 1e7
        K[6 * nd + 1, 6 * nd + 1] += 1e7
    K[2, 2] += 1e8  # axial
    om = 600.0
    # reference: state-space eigenvalues at Ω (free θz is a zero mode)
    minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ K, -minv @ (om * G)]])
    lam = np.linalg.eigvals(A)
    f_ref = np.sort(lam.imag[lam.imag > 1.0]) / (2 * math.pi)
    # time response: impulse on the disc's x, every node spinning at Ω
    v0 = np.zeros(n)
    v0[5::6] = om
    v0[d] = 1e-3
    from geardyn.models.transmission.integrate import stable_time_step

    dt = 0.8 * stable_time_step(M, K + np.diag(np.r_[np.zeros(n - 1), 1.0]))
    spin = {"s": list(range(5, n, 6))}
    rec, energy, done, status, q, v, _ = run_loop(
        np.zeros(n), v0, dt, int(2.0 / dt), 1, minv, K, np.zeros((n, n)), empty_bearings(),
        empty_meshes(), 5, 5, 5, 1.0, 1.0, 1.0, 0.0, np.array([0.0, 1e9]), np.zeros(2),
        0.0, 0.0, 0.0, 0.0, 1.0, np.array([d, d + 1], np.int64),
        gargs=gyroscopic_args({"s": G}, spin))
    assert status == 0
    r = rec[:, 2] + 1j * rec[:, 3]
    win = np.hanning(r.size)
    spec = np.abs(np.fft.fft(r * win, 8 * r.size))
    fr = np.fft.fftfreq(8 * r.size, dt)

    def peak(lo: float, hi: float) -> float:
        sel = np.flatnonzero((fr > lo) & (fr < hi))
        return float(fr[sel[np.argmax(spec[sel])]])

    fw = peak(0.5 * f_ref[0], 2.0 * f_ref[0])
    bw = -peak(-2.0 * f_ref[0], -0.3 * f_ref[0])
    # the first pair: backward below, forward above the non-spinning frequency
    assert bw == pytest.approx(f_ref[0], rel=1e-3)
    assert fw == pytest.approx(f_ref[1], rel=1e-3)
    assert f_ref[1] / f_ref[0] > 1.05  # a visible gyroscopic split
