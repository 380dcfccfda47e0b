"""Seed 003 run-up (ch. 4 §5, Figs 4.21-4.30) and load sharing during run-up (ch. 5 §2.2,
Figs 5.10-5.13): 36-DOF bench (Model A) and 12-DOF Model B with the test-ring support in
Table 3.1's printed unit (docs/validation.md, Hammami 2015 section); motor speed ramp imposed by
the speed control.

Thesis: the STFT of the simulated test-carrier acceleration during run-up (Figs 4.28-4.29,
torsional Model B) shows vertical lines at the natural frequencies 25 Hz and 144 Hz; the LSR
fluctuation period shrinks during run-up; measured: LSR of planet 1 grows and of planet 2 drops
with speed (pin errors 60/10/−60 µm).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import stft

from ._bench import f_mesh, raw, run, table_units

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


def _line(ds, dof: str, f0: float) -> tuple[float, float]:
    """STFT (Hann, 0.2 s, 75 % overlap, frames inside the record) of the DOF's acceleration;
    per frame, the largest bin within one bin of ``f0`` over the median of the bins 3 bins to
    40 Hz away. Returns (median ratio over frames, share of frames with ratio > 10). A line
    drawn in a colour map stands out by orders of magnitude in these runs (measured 150-920 in
    every frame where present, ≤ 3 where absent), so the verdict does not hang on the 10."""
    acc = np.gradient(ds.v.sel(dof=dof).values, DT)
    f, _, z = stft(acc, fs=1 / DT, nperseg=4096, noverlap=3072, boundary=None, padded=False)
    a = np.abs(z)
    i = int(np.argmin(np.abs(f - f0)))
    near = (np.abs(f - f0) > 3 * (f[1] - f[0])) & (np.abs(f - f0) < 40.0)
    ratio = a[i - 1 : i + 2].max(0) / np.median(a[near], axis=0)
    return float(np.median(ratio)), float(np.mean(ratio > 10.0))


@pytest.fixture(scope="module")
def runup_model_b():
    """The thesis's run-up model (torsional Model B, ch. 4 §2) with the test-ring support in
    Table 3.1's printed unit (test_model_b_ring_support.py)."""
    return run(table_units(_ramp(raw("planetary_bench_12dof.toml"), RPM0, RPM1, T_UP)), T_UP, DT)


def test_fig_4_29_carrier_line_144_hz(runup_model_b):
    """Figs 4.28-4.29: the STFT of the simulated test-carrier acceleration shows 144 Hz as a
    vertical line. Model B with the printed support unit: a line within one STFT bin (4.9 Hz;
    the thesis gives no STFT settings) of 144 Hz in ≥ 70 % of the frames — the rings winding
    the loop in opposition (143.1 Hz in eqs 4.2-4.6, 146.3 Hz in ours with the speed control),
    a torsional mode the carrier takes part in. Its 43.4 Hz companion (impact test 41 Hz)
    dominates the carrier; the thesis's 25 Hz is no mode of Model B (not reproduced)."""
    _, _, ds = runup_model_b
    level, share = _line(ds, "test.carrier.u", 144.0)
    assert share >= 0.7, (level, share)
    assert _line(ds, "test.carrier.u", 44.0)[1] >= 0.7


def test_model_a_lines_on_the_carrier(runup):
    """Model A (36-DOF, our reading of the support) during the same run-up: the loop mode
    through the soft planet bearings (26.87 Hz, reaction ring turning) is a line on the test
    carrier within one bin of the thesis's 25 Hz; its 139.96 Hz mode (ring translation, the
    former "144 Hz" match) is translational, so by the planets' symmetry it has no carrier
    rotation and no line on the carrier — the thesis's 144 Hz carrier line is not this mode."""
    _, _, ds = runup
    assert _line(ds, "test.carrier.u", 25.0)[1] >= 0.7
    level, share = _line(ds, "test.carrier.u", 144.0)
    assert share == 0.0 and level < 3.0


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
