"""Elapsed-time IAS (seed 002 eq 1) on a known speed law: quantisation bound and its growth
with speed; graduation errors; tacho; pulse generation from an angle history."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.sensors import (
    elapsed_time_ias,
    pulse_times_from_angle,
    quantisation_bound,
    simulate_ias,
    tacho_pulse_times,
)

R = 1000  # seed 002: 1000 pulses/rev
F_CLOCK = 80e6  # seed 002: 80 MHz
W0 = 200 * 2 * np.pi / 60  # 200 rpm
ALPHA = 40.0  # rad/s² (reaches ~900 rpm after 1.8 s)


def exact_pulse_times(n_rev: float) -> np.ndarray:
    """Edges at θ_k = k·2π/R of θ(t) = W0 t + ALPHA t²/2, inverted in closed form."""
    th = 2 * np.pi / R * np.arange(int(n_rev * R) + 1)
    return (-W0 + np.sqrt(W0**2 + 2 * ALPHA * th)) / ALPHA


def test_ias_error_within_quantisation_bound_and_grows_with_speed():
    tp = exact_pulse_times(15.0)  # 200 rpm → ~ 890 rpm
    m = elapsed_time_ias(tp, R, F_CLOCK, clock_phase=0.37)
    true_mean = (2 * np.pi / R) / np.diff(tp)  # interval-mean speed
    err = m.ias - true_mean
    # Quantisation: the measured elapsed time is within one clock period of the true one ...
    assert np.all(np.abs(m.ticks / F_CLOCK - np.diff(tp)) < 1.0 / F_CLOCK)
    # ... so the speed error stays inside the per-interval bound ias/(N-1).
    assert np.all(np.abs(err) <= m.bound)
    # The bound is the seed 002 "quantification ceiling" R ω²/(2π f_clock) to first order.
    np.testing.assert_allclose(m.bound, quantisation_bound(true_mean, R, F_CLOCK), rtol=0.01)
    # Error grows with speed (seed 002 §3.1): relative RMS error ∝ ω (RMS of a difference of
    # two independent uniform roundings: 1/√6 tick → rel. RMS = R ω/(2π f_clock √6)).
    slow = true_mean < 1.2 * W0
    fast = true_mean > 0.85 * true_mean.max()
    rel = err / true_mean
    for sel in (slow, fast):
        pred = R * true_mean[sel].mean() / (2 * np.pi * F_CLOCK * np.sqrt(6))
        assert np.sqrt(np.mean(rel[sel] ** 2)) == pytest.approx(pred, rel=0.15)
    assert np.sqrt(np.mean(err[fast] ** 2)) > 10 * np.sqrt(np.mean(err[slow] ** 2))


def test_ideal_clock_recovers_interval_mean_speed():
    tp = exact_pulse_times(2.0)
    m = elapsed_time_ias(tp, R, None)
    np.testing.assert_allclose(m.ias, (2 * np.pi / R) / np.diff(tp), rtol=1e-12)
    np.testing.assert_allclose(m.angle[:3], 2 * np.pi / R * np.arange(1, 4))


def test_pulse_times_from_sampled_angle_history_match_closed_form():
    t = np.linspace(0.0, 1.2, 200_001)  # ~6 samples per encoder interval at the top speed
    th = W0 * t + 0.5 * ALPHA * t**2
    tp = pulse_times_from_angle(t, th, R)
    exact = exact_pulse_times(th[-1] / (2 * np.pi))
    n = min(tp.size, exact.size)
    assert abs(tp.size - exact.size) <= 1
    # well below the 12.5 ns clock period
    assert np.max(np.abs(tp[:n] - exact[:n])) < 1e-10


def test_simulate_ias_from_a_speed_history():
    from geardyn.signal import angle_from_speed

    t = np.linspace(0.0, 1.0, 100_001)
    theta = angle_from_speed(t, W0 + ALPHA * t)  # trapezoid: exact for a linear speed law
    np.testing.assert_allclose(theta, W0 * t + 0.5 * ALPHA * t**2, rtol=1e-12, atol=1e-12)
    m = simulate_ias(t, theta)  # seed 002 defaults: 1000 pulses/rev, 80 MHz
    assert m.pulses_per_rev == 1000 and m.f_clock == 80e6
    exact = exact_pulse_times(theta[-1] / (2 * np.pi))
    true_mean = (2 * np.pi / R) / np.diff(exact)[: m.ias.size]
    assert np.all(np.abs(m.ias - true_mean) <= m.bound * 1.0001)


def test_graduation_error_gives_analytic_ias_pattern():
    w = 100.0  # rad/s, constant
    t = np.linspace(0, 0.2, 20_001)
    eps = 2e-4 * np.sin(2 * np.pi * 3 * np.arange(R) / R)  # 3 bumps per rev, rad
    tp = pulse_times_from_angle(t, w * t, R, graduation_error=eps)
    m = elapsed_time_ias(tp, R, None)
    k = np.arange(tp.size)
    d_eps = eps[k[1:] % R] - eps[k[:-1] % R]
    expected = w * (2 * np.pi / R) / (2 * np.pi / R + d_eps)
    np.testing.assert_allclose(m.ias, expected, rtol=1e-8)


def test_random_graduation_error_needs_seed_and_is_reproducible():
    t = np.linspace(0, 0.1, 5001)
    with pytest.raises(InputError, match="seed"):
        simulate_ias(t, 100 * t, graduation_error=1e-5)
    a = simulate_ias(t, 100 * t, graduation_error=1e-5, seed=3)
    b = simulate_ias(t, 100 * t, graduation_error=1e-5, seed=3)
    np.testing.assert_array_equal(a.ias, b.ias)


def test_once_per_rev_tacho_at_constant_speed():
    f_rot = 7.0
    t = np.linspace(0, 1, 10_001)
    tp = tacho_pulse_times(t, 2 * np.pi * f_rot * t + 0.1)
    np.testing.assert_allclose(np.diff(tp), 1 / f_rot, rtol=1e-9)
    assert tp.size == 7


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"f_clock": 0.0}, "f_clock"),
        ({"f_clock": 1e3}, "f_clock"),
        ({"pulses_per_rev": 0}, "pulses_per_rev"),
        ({"pulse_times": [0.0, 2.0, 1.0]}, "pulse_times"),
    ],
)
def test_bad_inputs_name_the_argument(kwargs, match):
    args = {"pulse_times": exact_pulse_times(0.1), "pulses_per_rev": R, "f_clock": F_CLOCK}
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        elapsed_time_ias(**args)
