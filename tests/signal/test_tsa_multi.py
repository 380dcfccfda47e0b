"""TSA of a shaft carrying several wheels: every mesh removed from the residual/difference
signals, and per-wheel localisation by each wheel's own unambiguous sidebands.

Closed forms: kurtosis of a sine 3/2, of Gaussian noise 3; TSA of white noise over N
revolutions has standard deviation σ/√N (seed 003 eq 1.25)."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.signal import (
    difference_signal,
    fm0,
    fm4,
    kurtosis,
    regular_signal,
    residual_signal,
    tsa,
)
from geardyn.signal.indicators import (
    energy_ratio,
    sideband_energy_ratio,
    sideband_kurtosis,
    wheel_indicators,
    wheel_sideband_orders,
)

SPR = 1024
TH = 2 * np.pi * np.arange(SPR) / SPR


def _mesh(z: int, amps=(1.0, 0.4, 0.2)) -> np.ndarray:
    return sum(a * np.cos((h + 1) * z * TH + 0.5 * h) for h, a in enumerate(amps))


def shared_shaft_tsa(fault: bool, seed: int = 0, nrev: int = 16) -> np.ndarray:
    """TSA of a shaft with a 19-tooth pinion and a 71-tooth wheel (the issue's case).

    Both meshes carry a 5 % once-per-rev modulation (eccentricity). The 19-tooth wheel's local
    fault is a 50 % amplitude modulation of its mesh by a Gaussian of 1.5 tooth pitches (full
    width at ±1σ), centred at 180° — the stiffness loss while the cracked tooth is in mesh.
    White noise σ = 0.05 per revolution (16 revolutions averaged)."""
    sigma = 1.5 * 2 * np.pi / 19 / 2
    g = np.exp(-0.5 * ((TH - np.pi) / sigma) ** 2)
    m19 = 1 + 0.05 * np.cos(TH) + (0.5 * g if fault else 0.0)
    m71 = 1 + 0.05 * np.cos(TH + 1.0)
    x = m19 * _mesh(19) + m71 * _mesh(71, (0.8, 0.1))
    rng = np.random.default_rng(seed)
    return tsa(np.tile(x, nrev) + rng.normal(0, 0.05, SPR * nrev), SPR)


def test_closed_forms_sine_and_gaussian():
    """FM4 = N Σd⁴/(Σd²)²: 1.5 for a sine (exact on whole periods), 3 for Gaussian noise
    (standard error √(24/N) ≈ 0.05 for N = 10⁴: tolerance 0.2)."""
    assert fm4(np.sin(5 * TH)) == pytest.approx(1.5, abs=1e-12)
    assert kurtosis(np.sin(5 * TH)) == pytest.approx(1.5, abs=1e-12)
    g = np.random.default_rng(1).normal(size=10_000)
    assert fm4(g) == pytest.approx(3.0, abs=0.2)


def test_removing_every_mesh_of_a_pure_multi_mesh_signal_leaves_zero():
    """A signal made only of the 19- and 71-tooth mesh harmonics and their ±1 sidebands: the
    difference signal removing both meshes is zero to round-off; the regular signal is the
    mesh part itself; removing only 19 leaves the 71 mesh."""
    x = _mesh(19) + _mesh(71, (0.8, 0.3)) + 0.1 * np.cos(18 * TH) + 0.05 * np.cos(72 * TH)
    assert np.max(np.abs(difference_signal(x, [19, 71]))) < 1e-12
    reg = regular_signal(x, (19, 71))
    assert np.max(np.abs(reg - (_mesh(19) + _mesh(71, (0.8, 0.3))))) < 1e-12
    only19 = residual_signal(x, 19)
    assert (
        np.max(
            np.abs(
                only19 - (_mesh(71, (0.8, 0.3)) + 0.1 * np.cos(18 * TH) + 0.05 * np.cos(72 * TH))
            )
        )
        < 1e-12
    )
    # backward compatible: an int and a one-element list agree
    assert np.array_equal(difference_signal(x, 19), difference_signal(x, [19]))
    # FM0 counts the mesh amplitudes of both wheels: 1+0.4+0.2+0.8+0.3 = 2.7
    assert fm0(x, (19, 71)) == pytest.approx((x.max() - x.min()) / 2.7, rel=1e-9)


def test_tsa_of_noise_falls_as_one_over_sqrt_n():
    """White noise σ = 1: std of the TSA over N revolutions is 1/√N (±10 %: SPR = 1024
    samples give a standard error of ~2.2 % on a standard deviation)."""
    rng = np.random.default_rng(7)
    for n in (4, 16, 64):
        t = tsa(rng.normal(size=SPR * n), SPR)
        assert np.std(t) == pytest.approx(1 / np.sqrt(n), rel=0.1)


def test_shared_shaft_fm4_needs_both_meshes_removed():
    """The issue's case: FM4 of the difference signal that removes only the 19-tooth mesh is
    pinned near a sine's 1.5 by the 71-tooth mesh (1.5–1.7 measured: 1.56 healthy, 1.60
    faulty), so the fault is missed; removing both meshes gives 10.6 (Gaussian-like healthy
    value 2.8), well above the usual FM4 alarm of 3 (Zakrajsek, Townsend & Decker 1993)."""
    healthy, faulty = shared_shaft_tsa(False), shared_shaft_tsa(True)
    assert 1.5 <= fm4(difference_signal(faulty, 19)) <= 1.7
    assert 1.5 <= fm4(difference_signal(healthy, 19)) <= 1.7
    assert fm4(difference_signal(healthy, (19, 71))) < 3.3
    assert fm4(difference_signal(faulty, (19, 71))) > 7.0
    # energy ratio counts both meshes in its regular signal
    assert energy_ratio(faulty, (19, 71)) > 1.5 * energy_ratio(healthy, (19, 71))


def test_wheel_sideband_orders_leave_out_the_other_wheels_neighbourhood():
    """19 and 71 teeth, J = 3: 19's sideband 73/74 (from 76) lie within ±3 of 71, and 71's
    73/74 within ±3 of 76 = 4·19: left out; 68, 69, 70, 72 stay for the 71 wheel."""
    mesh71, side71 = wheel_sideband_orders(SPR, 71, (19,), 3)
    assert mesh71[:2] == [71, 142]
    assert {68, 69, 70, 72} <= set(side71)
    assert not {73, 74} & set(side71)
    _, side19 = wheel_sideband_orders(SPR, 19, (71,), 3)
    assert {16, 17, 18, 20, 21, 22, 77, 78, 79} <= set(side19)
    assert not {73, 74} & set(side19)
    assert 75 in side19  # 76 − 1 is 4 orders from 71: unambiguous
    with pytest.raises(InputError, match="sidebands"):
        wheel_sideband_orders(SPR, 19, (71,), 0)


def test_faulty_wheel_localised_on_a_shared_shaft():
    """Per-wheel indicators on the wheel's own unambiguous sidebands (J = 3). Measured: 19-tooth
    SER 0.108 → 0.246 (×2.3) and sideband kurtosis 3.26 → 6.77 (×2.1) with the fault; the
    healthy 71-tooth wheel's SER (0.069) and sideband kurtosis (2.34, near 2.25 of a sinusoidal
    once-per-rev modulation) change by < 1 %. Asserted: faulty/healthy ≥ 1.8 for the 19 wheel,
    within 5 % for the 71 wheel, and the faulty wheel above the healthy one by ≥ 2.5×."""
    healthy, faulty = shared_shaft_tsa(False), shared_shaft_tsa(True)
    h19, f19 = (wheel_indicators(t, 19, (71,)) for t in (healthy, faulty))
    h71, f71 = (wheel_indicators(t, 71, (19,)) for t in (healthy, faulty))
    for key in ("SER", "sideband_kurtosis"):
        assert f19[key] >= 1.8 * h19[key]
        assert f71[key] == pytest.approx(h71[key], rel=0.05)
    assert f19["SER"] >= 2.5 * f71["SER"]
    assert f19["sideband_kurtosis"] >= 2.5 * f71["sideband_kurtosis"]
    assert f19["NB4"] > h19["NB4"]
    assert f71["NB4"] == pytest.approx(h71["NB4"], rel=0.05)
    # a pure sinusoidal modulation cos θ·cos 71θ rebuilt from ±1 sidebands: kurtosis 9/4
    x = (1 + 0.1 * np.cos(TH)) * np.cos(71 * TH)
    assert sideband_kurtosis(x, 71, (19,)) == pytest.approx(2.25, rel=1e-9)
    # SER = (0.05 + 0.05) / 1 for that modulation
    assert sideband_energy_ratio(x, 71, (19,)) == pytest.approx(0.1, rel=1e-9)


def test_synchronous_energy_ratio_is_unbiased_by_non_synchronous_noise():
    """x = sin 20θ + 0.1 cos 45θ + white noise σ = 0.5, 16 revolutions of 256 samples: true ER
    = 0.1/1 (Zakrajsek et al. 1993 definition). The TSA keeps 1/16 of the noise power, so
    ER of the TSA reads 0.18–0.19 over 20 seeds; from unbiased synchronous powers (Braun 1975)
    it reads 0.095 ± 0.018 (mean ± σ over seeds). Asserted on seeds 0–4: TSA ER > 0.15 and
    synchronous ER within 0.1 ± 0.05; the power at order 20 equals 1 (A²) within 5 %."""
    from geardyn.signal.indicators import synchronous_energy_ratio, synchronous_power

    n = 16
    th = 2 * np.pi * np.arange(256 * n) / 256
    for seed in range(5):
        x = np.sin(20 * th) + 0.1 * np.cos(45 * th)
        x = x + np.random.default_rng(seed).normal(0, 0.5, th.size)
        assert energy_ratio(tsa(x, 256), 20) > 0.15
        er, drms = synchronous_energy_ratio(x, 256, 20)
        assert er == pytest.approx(0.1, abs=0.05)
        assert synchronous_power(x, 256)[20] == pytest.approx(1.0, rel=0.05)
    with pytest.raises(InputError, match="at least 2 whole revolutions"):
        synchronous_power(np.ones(300), 256)


def test_planetary_tsa_detrend_removes_pass_to_pass_level_changes():
    """A planet tooth pulse (the planetary-TSA case of test_diagnosis) plus a level that changes
    from one carrier revolution to the next (load sharing, ±5 units), both seen through the
    planet-pass lobe: without ``detrend`` the pieces' lobe-shaped levels leave steps in the
    average (low orders 1–3 above 0.3); removing a weighted quadratic from each piece first
    (``detrend=2``) leaves < 0.05 there, and the pulse keeps its position (tooth 5) and most
    of its height (> 0.7 of the unit pulse)."""
    from geardyn.signal import planetary_tsa

    zr, zp, n_pl, spt, revs = 65, 24, 3, 32, 48
    spc = zr * spt
    m = np.arange(spc * revs) / spt
    theta = 2 * np.pi * m / zr
    rel = (theta + np.pi / n_pl) % (2 * np.pi)
    win0 = np.where(rel < 2 * np.pi / n_pl, 0.5 * (1 - np.cos(n_pl * rel)), 0.0)
    dm = (m - 5.0 + zp / 2) % zp - zp / 2
    level = np.repeat(np.random.default_rng(2).uniform(-5, 5, revs), spc)
    x = win0 * (np.exp(-0.5 * (dm * spt / 2.0) ** 2) + level)
    plain = planetary_tsa(x, spc, zr, zp, n_pl, planet=0, window_teeth=8)
    flat = planetary_tsa(x, spc, zr, zp, n_pl, planet=0, window_teeth=8, detrend=2)

    def low(a):
        return np.max(np.abs(np.fft.rfft(a - a.mean()))[1:4] * 2 / a.size)

    assert low(plain) > 0.3
    assert low(flat) < 0.05
    assert int(np.argmax(flat)) == pytest.approx(5 * spt, abs=2)
    assert flat.max() - np.median(flat) > 0.7
