"""Seed 003 run-up (ch. 4 §5, Figs 4.21-4.30) and load sharing during run-up (ch. 5 §2.2,
Figs 5.10-5.13), 36-DOF bench (Model A; notes §4.2: the torsional 12-DOF model has neither the
25 Hz nor the 144 Hz mode), motor speed ramp imposed by the speed control.

Thesis: the simulated run-up STFT shows inclined lines (mesh harmonics) and vertical lines at the
excited natural frequencies 25 Hz and 144 Hz; the LSR fluctuation period shrinks during run-up;
measured: LSR of planet 1 grows and of planet 2 drops with speed (pin errors 60/10/−60 µm).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import find_peaks, stft

from ._bench import f_mesh, raw, run

RPM0, RPM1, T_UP = 100.0, 1498.5, 1.0
DT = 5e-5


def _ramp(d: dict, rpm0: float, rpm1: float, t_end: float) -> dict:
    sim = d["planetary_dynamics"]["simulation"]
    body = sim["speed_controls"][0]["body"]
    sim["initial_speed_rpm"] = {body: rpm0}
    sim["speed_controls"][0]["profile_rpm"] = [[0.0, rpm0], [t_end, rpm1]]
    sim["torques"] = [{"body": "reaction.ring", "torque_nm": 100.0}]
    return d


@pytest.fixture(scope="module")
def runup():
    return run(_ramp(raw("planetary_bench_36dof.toml"), RPM0, RPM1, T_UP), T_UP, DT)


def _vertical_lines(ds, dof: str) -> tuple[np.ndarray, np.ndarray]:
    """STFT (Hann, 0.2 s, 75 % overlap) of the DOF's acceleration; per frequency bin, the
    fraction of frames in which it is a spectral peak (≥ 5 % of the frame maximum)."""
    acc = np.gradient(ds.v.sel(dof=dof).values, DT)
    f, _, z = stft(acc, fs=1 / DT, nperseg=4096, noverlap=3072)
    a = np.abs(z)
    hits = np.zeros(f.size)
    for j in range(a.shape[1]):
        pk, _ = find_peaks(a[:, j], prominence=0.05 * a[:, j].max())
        hits[pk] += 1
    return f, hits / a.shape[1]


@pytest.mark.parametrize(("dof", "thesis_hz", "model_hz", "tol"),
                         [("test.ring.u", 25.0, 26.87, 0.10), ("test.ring.x", 144.0, 139.96, 0.05)])
def test_stft_vertical_lines(runup, dof, thesis_hz, model_hz, tol):
    """A frequency that stays a spectral peak in ≥ 70 % of the frames (a vertical STFT line)
    lies within ``tol`` of the thesis's 25/144 Hz and within one STFT bin (4.9 Hz) of our modal
    frequency (26.87 Hz reaction-ring rotation, 139.96 Hz ring translation, test_modal_low_band);
    the inclined mesh lines sweep through and are a peak in few frames only."""
    _, _, ds = runup
    f, share = _vertical_lines(ds, dof)
    near = np.abs(f - thesis_hz) <= tol * thesis_hz
    assert share[near].max() >= 0.7
    line = f[near][np.argmax(share[near])]
    assert line == pytest.approx(model_hz, abs=f[1] - f[0])


LSR_RPM0, LSR_RPM1, LSR_T, LSR_DT = 100.0, 500.0, 1.0, 1e-4


@pytest.fixture(scope="module")
def lsr_runup():
    d = _ramp(raw("planetary_bench_36dof.toml"), LSR_RPM0, LSR_RPM1, LSR_T)
    for st in d["planetary_dynamics"]["stages"]:
        if st["stage"] == "test":
            st["pin_errors_m"] = [60e-6, 10e-6, -60e-6]  # seed 003 ch. 5 §2.1.3
    sim = d["planetary_dynamics"]["simulation"]
    sim["modal_damping_ratio"] = 0.02
    # load direction in which a positive (lagging) pin error preloads its planet (the thesis's
    # "100 N.m of input torque" gives no sign)
    sim["torques"][0]["torque_nm"] = -100.0
    return run(d, LSR_T, LSR_DT)


def test_lsr_fluctuation_follows_the_mesh(lsr_runup):
    """Figs 5.10-5.11: the LSR fluctuation period shrinks with speed, i.e. it stays locked to
    the mesh period 1/f_m(t). Resampled to the mesh-cycle count φ(t) = ∫f_m dt of the ramp,
    LSR_1 in 0.65-0.95 s has a line at mesh order 1 at least 3 times the median level of the
    orders 0.7-1.3 around it."""
    _, _, ds = lsr_runup
    t = ds.time.values
    rpm = LSR_RPM0 + (LSR_RPM1 - LSR_RPM0) * t / LSR_T
    fm = f_mesh(rpm)
    phi = np.concatenate([[0.0], np.cumsum(0.5 * (fm[1:] + fm[:-1]) * np.diff(t))])
    s = (t >= 0.65) & (t < 0.95)
    g = np.linspace(phi[s][0], phi[s][-1], 4096)
    y = np.interp(g, phi[s], ds.lsr_test.values[s, 0])
    y = y - y.mean()
    amp = np.abs(np.fft.rfft(y * np.hanning(y.size)))
    order = np.fft.rfftfreq(y.size, g[1] - g[0])
    near = (np.abs(order - 1) < 0.3) & (np.abs(order - 1) > 0.08)
    assert amp[np.argmin(np.abs(order - 1))] >= 3 * np.median(amp[near])


def test_lsr_order_with_pin_errors(lsr_runup):
    """Ch. 5 §2.1.3: planet 1 (+60 µm) is preloaded first and carries most, planet 3 (−60 µm)
    least; sum = 1."""
    _, _, ds = lsr_runup
    sel = ds.sel(time=slice(0.2, None)).lsr_test.values
    np.testing.assert_allclose(sel.sum(1), 1.0, rtol=1e-9)
    m = sel.mean(0)
    assert m[0] > m[1] > m[2]


def test_lsr_trend_during_runup_pinned(lsr_runup):
    # regression guard (no source value): measured (Fig 5.13), LSR_1 grows and LSR_2 drops
    # during run-up; ours barely moves (the pin errors act quasi-statically; the thesis gives
    # no simulated trend). Pinned: window means of LSR_1, LSR_2 at 0.2-0.4 s
    # and 0.8-1.0 s, to 2e-3.
    _, _, ds = lsr_runup
    early = ds.sel(time=slice(0.2, 0.4)).lsr_test.values.mean(0)
    late = ds.sel(time=slice(0.8, 1.0)).lsr_test.values.mean(0)
    np.testing.assert_allclose(early[:2], _PIN_EARLY, atol=2e-3)
    np.testing.assert_allclose(late[:2], _PIN_LATE, atol=2e-3)


_PIN_EARLY = [0.4578, 0.3480]
_PIN_LATE = [0.4504, 0.3473]
