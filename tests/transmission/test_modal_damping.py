"""Modal damping without the dense n² product (issue 12, :func:`geardyn.solve.explicit.
modal_damping`): damping ratios recovered from free decays of single modes integrated by the
explicit loop (logarithmic decrement, e.g. Inman, *Engineering Vibration*, 4th ed., 2014, §1.6:
ζ = δ / √(4π² + δ²)), ζ below the cutoff and ζ f/f_c above it; the damping energy channel
against the loss of mechanical energy; the seed 002 run against the dense modal damping."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import eigh

from geardyn.config.loader import load_config, parse_config
from geardyn.elements import ShaftSection, timoshenko_element
from geardyn.errors import ConfigError, InputError
from geardyn.solve.explicit import (
    E_MODAL,
    damped_step_limit,
    modal_damping,
    run_loop,
    stable_time_step,
)
from tests.transmission._empty import empty_bearings, empty_meshes

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "seed002_transmission.toml"
ZETA = 0.005


def _supported_shaft(mass: str = "lumped") -> tuple[np.ndarray, np.ndarray]:
    """Ø40 mm × 0.8 m steel shaft, 8 elements, on springs (1e7 N/m radial at both ends,
    1e8 N/m axial and 1e3 N·m/rad torsional at node 0): no rigid modes."""
    s = ShaftSection(0.04)
    ne, length = 8, 0.8
    n = 6 * (ne + 1)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    ke, me = timoshenko_element(length / ne, s, mass)
    for e in range(ne):
        K[6 * e : 6 * e + 12, 6 * e : 6 * e + 12] += ke
        M[6 * e : 6 * e + 12, 6 * e : 6 * e + 12] += me
    for nd in (0, ne):
        K[6 * nd, 6 * nd] += 1e7
        K[6 * nd + 1, 6 * nd + 1] += 1e7
    K[2, 2] += 1e8
    K[5, 5] += 1e3
    return K, M


def _decay(K, M, C, shape, dt, n_steps) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Free decay from q0 = ``shape`` (v0 = 0) with :func:`run_loop`: (t, q(t), energy)."""
    n = K.shape[0]
    rec, energy, done, status, q, v, _ = run_loop(
        shape.copy(), np.zeros(n), dt, n_steps, 1, np.linalg.inv(M), K, C, empty_bearings(),
        empty_meshes(), 5, 5, 5, 1.0, 1.0, 1.0, 0.0, np.array([0.0, 1e9]), np.zeros(2),
        0.0, 0.0, 0.0, 0.0, 1.0, np.arange(n, dtype=np.int64))
    assert status == 0 and done == n_steps
    return rec[:, 0], rec[:, 2 : 2 + n], energy, q, v


def _log_decrement_ratio(eta: np.ndarray) -> float:
    """ζ from the logarithmic decrement of the positive peaks of a decaying oscillation."""
    i = np.flatnonzero((eta[1:-1] > eta[:-2]) & (eta[1:-1] >= eta[2:])) + 1
    pk = eta[i]
    m = pk.size - 1
    delta = math.log(pk[0] / pk[-1]) / m
    return delta / math.sqrt(4 * math.pi**2 + delta**2)


def test_ratios_recovered_from_free_decays() -> None:
    """Cutoff between modes 5 and 6: modes 1 and 5 decay with ζ (1 %), the first mode above
    3 f_c with ζ f/f_c (2 %); the operator's ``ratios`` say the same. Integrated with
    ω dt ≤ 0.03 and half the damped stability limit."""
    K, M = _supported_shaft()
    w2, phi = eigh(K, M)
    f = np.sqrt(w2) / (2 * math.pi)
    cutoff = 0.5 * (f[5] + f[6])
    op = modal_damping(M, K, ZETA, cutoff)
    assert op.basis.shape[1] == 6  # modes 0-5 retained (no rigid modes)
    assert np.allclose(op.ratios[:6], ZETA, rtol=1e-12)
    hi = int(np.argmax(f > 3 * cutoff))
    assert op.ratios[hi] == pytest.approx(ZETA * f[hi] / cutoff, rel=1e-12)
    dt_lim = stable_time_step(M, K) * 0.5 * damped_step_limit(op.ratios[-1])
    for mode, expected in ((1, ZETA), (5, ZETA), (hi, ZETA * f[hi] / cutoff)):
        dt = min(0.03 / (2 * math.pi * f[mode]), 0.5 * dt_lim)
        n_steps = int(8 / f[mode] / dt)
        t, q, energy, qe, ve = _decay(K, M, op, 1e-4 * phi[:, mode], dt, n_steps)
        eta = q @ (M @ phi[:, mode])  # modal coordinate (mass-normalised shapes)
        tol = 0.01 if mode < 6 else 0.02
        assert _log_decrement_ratio(eta) == pytest.approx(expected, rel=tol), mode
        # the other modes stay unexcited: damping does not couple them
        other = q @ (M @ phi[:, mode + 1])
        assert np.max(np.abs(other)) < 1e-6 * np.max(np.abs(eta))
        # energy channel = loss of mechanical energy (½vᵀMv + ½qᵀKq)
        e0 = 0.5 * (1e-4 * phi[:, mode]) @ K @ (1e-4 * phi[:, mode])
        e1 = 0.5 * ve @ M @ ve + 0.5 * qe @ K @ qe
        assert energy[E_MODAL] == pytest.approx(e0 - e1, rel=1e-3)


def test_dense_and_truncated_agree_below_the_cutoff() -> None:
    """The truncated operator equals the dense modal damping matrix M Φ diag(2ζω) Φᵀ M on the
    retained modes (projections to 1e-9 of the diagonal), consistent mass as well."""
    from geardyn.models.transmission.assembly import modal_damping_matrix

    K, M = _supported_shaft("consistent")
    w2, phi = eigh(K, M)
    f = np.sqrt(w2) / (2 * math.pi)
    op = modal_damping(M, K, ZETA, 0.5 * (f[5] + f[6]))
    C = op.stiffness + op.basis @ np.diag(op.weights) @ op.basis.T
    Cd = modal_damping_matrix(M, K, ZETA)
    pr = phi[:, :6]
    scale = np.max(np.abs(pr.T @ Cd @ pr))
    assert np.max(np.abs(pr.T @ C @ pr - pr.T @ Cd @ pr)) < 1e-9 * scale
    # above the cutoff: diagonal in the modes, ratio ζ f/f_c
    ph = phi[:, 6:]
    D = ph.T @ C @ ph
    assert np.max(np.abs(D - np.diag(np.diag(D)))) < 1e-9 * np.max(np.abs(D))
    assert np.allclose(np.diag(D) / (2 * 2 * math.pi * f[6:]), ZETA * f[6:] / op_cut(op, f),
                       rtol=1e-9)


def op_cut(op, f: np.ndarray) -> float:  # noqa: ANN001
    """Cutoff recovered from the ratio of the first mode above it."""
    i = op.basis.shape[1]
    return float(ZETA * f[i] / op.ratios[i])


def test_bad_cutoff_is_named() -> None:
    K, M = _supported_shaft()
    with pytest.raises(InputError, match="cutoff"):
        modal_damping(M, K, ZETA, float("nan"))
    d = load_config(EXAMPLE).model_dump(exclude_none=True)
    d["transmission"]["modal_damping_cutoff_hz"] = -1.0
    with pytest.raises(ConfigError, match="modal_damping_cutoff_hz"):
        parse_config(d)


def test_cutoff_below_the_lowest_elastic_mode_is_refused() -> None:
    """A cutoff at or below the lowest elastic mode would give every mode ζ f/f_c (up to
    ≈ 2700 on the top mode of seed 002 at 0.1 Hz) and shrink the damped step by orders of
    magnitude: refused before the run, naming the field and the lowest mode."""
    from geardyn.run import run_simulation

    d = load_config(EXAMPLE).model_dump(exclude_none=True)
    d["transmission"]["modal_damping_cutoff_hz"] = 0.1
    with pytest.raises(ConfigError, match=r"modal_damping_cutoff_hz: 0.1 Hz is at or below "
                                          r"the lowest elastic mode \(75"):
        run_simulation(parse_config(d), revolutions=0.05)


def test_seed002_run_with_truncated_damping() -> None:
    """Seed 002, 0.3 revolution from 360 rpm with the modal damping above 2 kHz replaced by
    the stiffness-proportional term: the stable step is the damped limit of the highest mode,
    the mean mesh forces and the output speed stay within 0.5 % of the dense modal damping run,
    and the energy balance still closes (status ok)."""
    from geardyn.models.transmission import build_model, prepare, simulate
    from geardyn.models.transmission.simulate import damping_operator

    d = load_config(EXAMPLE).model_dump(exclude_none=True)
    d["transmission"]["speed_law"].update(start_rpm=360.0, end_rpm=360.0)
    d["transmission"]["simulation"]["integrator"] = "explicit"  # its damped step limit
    cfg = parse_config(d)
    prep = prepare(build_model(cfg), "output")
    op, dt_lim = damping_operator(prep, 2000.0)
    xi = float(op.ratios[-1])
    w_max = math.sqrt(eigh(prep.K_lin, prep.model.M, eigvals_only=True)[-1])
    assert dt_lim == pytest.approx(damped_step_limit(xi) / w_max, rel=1e-9)
    assert 0.0 < xi < 0.2
    dense = simulate(cfg, revolutions=0.3, prepared=prep)
    d["transmission"]["modal_damping_cutoff_hz"] = 2000.0
    trunc = simulate(parse_config(d), revolutions=0.3, prepared=prep)
    assert trunc.attrs["status"] == "ok" and dense.attrs["status"] == "ok"
    assert trunc.attrs["time_step_s"] < dense.attrs["time_step_s"]
    fm_d = dense["mesh_force"].mean("time").values
    fm_t = trunc["mesh_force"].mean("time").values
    assert np.allclose(fm_t, fm_d, rtol=5e-3)
    sp = dense["speed"].sel(shaft="output").values
    st = trunc["speed"].sel(shaft="output").values
    assert st.mean() == pytest.approx(sp.mean(), rel=5e-3)
    assert stable_time_step(prep.model.M, prep.K_lin) == pytest.approx(prep.dt_stable)


def _radius(wh: float, xi: float) -> float:
    """Spectral radius of the loop's one-mode amplification matrix on (q, v, a) (ω = 1):
    v_h = v + h a/2, q' = q + h v_h, a' = −q' − 2ξ (v + h a), v' = v_h + h a'/2."""
    A = np.empty((3, 3))
    for j in range(3):
        q, v, a = np.eye(3)[j]
        vh = v + 0.5 * wh * a
        q1 = q + wh * vh
        a1 = -q1 - 2.0 * xi * (v + wh * a)
        A[:, j] = (q1, vh + 0.5 * wh * a1, a1)
    return float(np.max(np.abs(np.linalg.eigvals(A))))


@pytest.mark.parametrize("xi", [0.0, 0.05, 0.2, 0.8])
def test_damped_step_limit(xi: float) -> None:
    """2(√(1+4ξ²) − 2ξ) against the amplification matrix (radius ≤ 1 just below, > 1 just
    above), and in the time domain: a damped oscillator (ω = 1000 rad/s) integrated by the loop
    decays at 0.98 × the limit and blows up at 1.02 × (dense damping path)."""
    lim = damped_step_limit(xi)
    assert _radius(0.999 * lim, xi) <= 1.0 + 1e-9
    assert _radius(1.001 * lim, xi) > 1.0 + 1e-6
    if xi == 0.0:
        assert lim == pytest.approx(2.0, rel=1e-12)
        return
    w = 1000.0
    M = np.eye(6)
    K = np.diag([w * w, 1.0, 1.0, 1.0, 1.0, 1.0])
    C = np.diag([2 * xi * w, 0.0, 0.0, 0.0, 0.0, 0.0])
    q0 = np.array([1e-3, 0, 0, 0, 0, 0.0])
    for factor, grows in ((0.98, False), (1.02, True)):
        rec, _, done, status, q, v, _ = run_loop(
            q0.copy(), np.zeros(6), factor * lim / w, 3000, 1, M, K, C, empty_bearings(),
            empty_meshes(), 5, 5, 5, 1.0, 1.0, 1.0, 0.0, np.array([0.0, 1e9]), np.zeros(2),
            0.0, 0.0, 0.0, 0.0, 1.0, np.array([0], np.int64))
        amp = np.max(np.abs(rec[-500:, 2])) if status == 0 else np.inf
        assert (amp > 1e-2) == grows, (factor, amp)
