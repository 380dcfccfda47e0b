"""Sensor models against hand computations and closed forms (issue 12, mutation-testing gaps).

- IAS by the elapsed-time method (seed 002 eq 1, ``IAS_i = 2π f_clock/(R N_i)``): counter values
  computed by hand for known edge times, with the clock frequency and phase varied (a parameter
  the other tests keep at 80 MHz), the quantisation bound ``ias/(N − 1)`` and the seed 002 §3.1
  ceiling ``R ω²/(2π f_clock)``;
- accelerance path ``H(s) = s²/(m (s² + 2ζωs + ω²))``: resonance ``j/(2ζm)``, mass line ``1/m``,
  and the digital filter as the bilinear transform in closed form (pre-warped);
- planet-pass windows at the passage angle (seed 003 eqs 4.10-4.12) and the §4.1 rule;
- every bad input names its argument and the rule.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal as sps

from geardyn.errors import InputError
from geardyn.sensors.encoder import (
    elapsed_time_ias,
    pulse_times_from_angle,
    quantisation_bound,
    quantise_clock,
    simulate_ias,
    tacho_pulse_times,
)
from geardyn.sensors.planet_pass import (
    dominant_carrier_orders,
    planet_pass_signal,
    planet_pass_windows,
)
from geardyn.sensors.transfer import accelerance, apply_transfer_path, mode_filter

# ---- IAS, seed 002 eq 1 -------------------------------------------------------------------

# edges of a shaft at 50 rev/s with R = 4: Δt = 5 ms; clock 1 kHz → 5 ticks per interval
EDGES = np.array([0.0123, 0.0173, 0.0223, 0.0273, 0.0331])


@pytest.mark.parametrize("f_clock, phase", [(1000.0, 0.0), (1000.0, 0.75), (3000.0, 0.4)])
def test_elapsed_time_ias_by_hand(f_clock: float, phase: float):
    """Counter N_k = floor(t_k f + φ) latched at each edge; N_i = N_k − N_(k−1);
    IAS_i = 2π f/(R N_i); bound ias/(N_i − 1); edge times N_k/f."""
    counts = [math.floor(t * f_clock + phase) for t in EDGES]
    np.testing.assert_array_equal(quantise_clock(EDGES, f_clock, phase), counts)
    ticks = np.diff(counts)
    m = elapsed_time_ias(EDGES, 4, f_clock, clock_phase=phase)
    np.testing.assert_array_equal(m.ticks, ticks)
    ias = [2 * math.pi * f_clock / (4 * n) for n in ticks]
    np.testing.assert_allclose(m.ias, ias, rtol=1e-14)
    np.testing.assert_allclose(m.bound, np.array(ias) / (ticks - 1), rtol=1e-14)
    np.testing.assert_allclose(m.time, np.array(counts[1:]) / f_clock, rtol=1e-14)
    np.testing.assert_allclose(m.angle, 2 * math.pi / 4 * np.arange(1, 5), rtol=1e-14)
    assert m.f_clock == f_clock and m.pulses_per_rev == 4


def test_phase_shifts_the_latched_counts():
    """φ = 0.75 with t f = 12.3 latches 13 instead of 12 (hand value)."""
    assert quantise_clock(EDGES, 1000.0, 0.75)[0] == 13
    assert quantise_clock(EDGES, 1000.0, 0.0)[0] == 12


def test_two_ticks_is_the_slowest_clock_accepted():
    """N = 2 per interval is accepted (bound = ias), N = 1 is refused."""
    tp = np.array([0.0, 0.002, 0.004])
    m = elapsed_time_ias(tp, 10, 1000.0, clock_phase=0.5)
    np.testing.assert_array_equal(m.ticks, [2, 2])
    np.testing.assert_allclose(m.bound, m.ias)
    with pytest.raises(InputError, match="f_clock: fewer than 2 clock ticks"):
        elapsed_time_ias(tp, 10, 500.0, clock_phase=0.5)


def test_two_edges_give_one_sample_and_the_ideal_clock_has_no_bound():
    m = elapsed_time_ias(np.array([0.1, 0.3]), 8, None)
    assert m.ias.shape == (1,)
    assert m.ias[0] == pytest.approx(2 * math.pi / 8 / 0.2, rel=1e-14)
    assert m.bound[0] == 0.0 and math.isinf(m.f_clock)
    np.testing.assert_allclose(m.time, [0.3])


@pytest.mark.parametrize("f_clock", [1e6, 80e6])
def test_quantisation_bound_closed_form(f_clock: float):
    """Seed 002 §3.1: bound = ω/N with N = 2π f/(R ω), i.e. R ω²/(2π f)."""
    w = np.array([10.0, 100.0])
    np.testing.assert_allclose(quantisation_bound(w, 1000, f_clock),
                               1000 * w**2 / (2 * math.pi * f_clock), rtol=1e-14)
    assert quantisation_bound(50.0, 360, f_clock) == pytest.approx(
        50.0 / (2 * math.pi * f_clock / (360 * 50.0)), rel=1e-14)


def test_simulate_ias_passes_clock_frequency_and_phase():
    """Constant speed 2π·10 rad/s, R = 5: edges at t_k = k/50 s; a 1025 Hz clock latches
    floor(20.5 k + φ): ticks 21, 20, 21, … for φ = 0.75 and 20, 21, 20, … for φ = 0.1."""
    t = np.linspace(0.0, 0.5, 2001)
    th = 2 * math.pi * 10 * t
    k = np.arange(26)
    for phase in (0.75, 0.1):
        m = simulate_ias(t, th, pulses_per_rev=5, f_clock=1025.0, clock_phase=phase)
        counts = np.floor(20.5 * k + phase)
        np.testing.assert_array_equal(m.ticks, np.diff(counts))
        np.testing.assert_allclose(m.ias, 2 * math.pi * 1025.0 / (5 * np.diff(counts)),
                                   rtol=1e-14)
        np.testing.assert_allclose(m.time, counts[1:] / 1025.0, rtol=1e-14)


def test_tacho_pulses_at_whole_revolutions():
    """Once-per-rev pulses of θ = 2π·4 t sit at t = k/4 (offset 0 by default), at k/4 + 1/16
    with a quarter-turn offset."""
    t = np.linspace(0.0, 1.0, 4001)
    th = 2 * math.pi * 4 * t
    np.testing.assert_allclose(tacho_pulse_times(t, th), np.arange(5) / 4, atol=1e-12)
    np.testing.assert_allclose(tacho_pulse_times(t, th, angle_offset=math.pi / 2),
                               np.arange(4) / 4 + 1 / 16, atol=1e-12)


@pytest.mark.parametrize("call, message", [
    (lambda: elapsed_time_ias(EDGES, 0, 1e3), r"pulses_per_rev: encoder resolution must be >= 1"),
    (lambda: elapsed_time_ias(EDGES, 4, -1.0), r"f_clock: clock frequency \[Hz\] must be > 0"),
    (lambda: elapsed_time_ias(EDGES[:1], 4, 1e3),
     r"pulse_times: pulse times needs at least 2 samples"),
    (lambda: elapsed_time_ias(EDGES[::-1], 4, 1e3), r"pulse_times: .* strictly increasing"),
    (lambda: quantise_clock(EDGES, 0.0), r"f_clock: clock frequency \[Hz\] must be > 0"),
    (lambda: quantise_clock(EDGES[:1], 1e3), r"pulse_times: pulse times needs at least 2"),
    (lambda: quantise_clock(EDGES[::-1], 1e3), r"pulse_times: .* strictly increasing"),
    (lambda: quantise_clock(EDGES, 1e3, 1.0), r"clock_phase: must be in \[0, 1\), got 1.0"),
    (lambda: quantisation_bound(1.0, 0, 1e3), r"pulses_per_rev: encoder resolution must be"),
    (lambda: quantisation_bound(1.0, 4, 0.0), r"f_clock: clock frequency \[Hz\] must be > 0"),
])
def test_ias_bad_input_names_the_argument(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_clock_phase_just_below_one_is_accepted():
    assert quantise_clock(EDGES, 1000.0, 0.999)[0] == 13


def test_pulse_times_need_forward_rotation():
    t = np.linspace(0, 1, 50)
    with pytest.raises(InputError, match="angle: .*shaft must turn forward"):
        pulse_times_from_angle(t, -t, 10)


# ---- accelerance path ---------------------------------------------------------------------

MODES = [{"frequency_hz": 800.0, "damping_ratio": 0.04, "modal_mass_kg": 2.5},
         {"frequency_hz": 2500.0, "damping_ratio": 0.1, "modal_mass_kg": 0.7}]


def test_accelerance_resonance_and_mass_line():
    """One mode: H(jω_n) = j/(2ζm) (quadrature, magnitude 1/(2ζm)); H → 1/m far above; H(0) = 0.
    Two modes: the sum of the two single-mode closed forms."""
    one = MODES[:1]
    h = accelerance(np.array([0.0, 800.0, 8e6]), one)
    assert h[0] == 0
    assert h[1] == pytest.approx(1j / (2 * 0.04 * 2.5), rel=1e-12)
    assert h[2] == pytest.approx(1 / 2.5, rel=1e-4)
    f = np.array([300.0, 1700.0])
    s = 2j * np.pi * f
    want = sum(s * s / (md["modal_mass_kg"] * (s * s + 2 * md["damping_ratio"]
                                               * (2 * np.pi * md["frequency_hz"]) * s
                                               + (2 * np.pi * md["frequency_hz"]) ** 2))
               for md in MODES)
    np.testing.assert_allclose(accelerance(f, MODES), want, rtol=1e-12)


def test_accelerance_defaults_are_unit_mass_and_five_percent():
    h = accelerance(np.array([500.0]), [{"frequency_hz": 500.0}])
    assert h[0] == pytest.approx(1j / (2 * 0.05 * 1.0), rel=1e-12)


def test_digital_mode_is_the_prewarped_bilinear_transform():
    """Bilinear transform: the digital response at f equals the analog one at
    ω_a = 2 fs tan(π f/fs), with the mode pre-warped to w = 2 fs tan(π f_n/fs); so at f_n the
    digital peak is exactly j/(2ζm)."""
    fs, fn, z, m = 10_000.0, 1500.0, 0.03, 1.7
    b, a = mode_filter(fn, z, m, fs)
    f = np.array([200.0, 1500.0, 3000.0, 4400.0])
    _, hd = sps.freqz(b, a, worN=f, fs=fs)
    w = 2 * fs * math.tan(math.pi * fn / fs)
    s = 2j * fs * np.tan(np.pi * f / fs)
    np.testing.assert_allclose(hd, s * s / (m * (s * s + 2 * z * w * s + w * w)), rtol=1e-9)
    assert hd[1] == pytest.approx(1j / (2 * z * m), rel=1e-9)


def test_transfer_path_steady_sine_and_static_load():
    """A force F₀ + A sin(2π f_n t) through one mode: the static part gives no acceleration,
    the steady response amplitude is A/(2ζm) (closed form at resonance)."""
    fs, fn, z, m = 20_000.0, 1000.0, 0.05, 2.0
    t = np.arange(0, 0.5, 1 / fs)
    force = 300.0 + 4.0 * np.sin(2 * np.pi * fn * t)
    acc = apply_transfer_path(force, fs, [{"frequency_hz": fn, "damping_ratio": z,
                                           "modal_mass_kg": m}])
    tail = acc[t > 0.3]
    assert np.abs(tail).max() == pytest.approx(4.0 / (2 * z * m), rel=0.01)
    assert abs(tail.mean()) < 0.01 * 4.0 / (2 * z * m)
    static = apply_transfer_path(np.full(400, 300.0), fs, MODES)
    assert np.abs(static).max() == 0.0


@pytest.mark.parametrize("args, message", [
    ((0.0, 0.05, 1.0, 1e4), r"frequency_hz: mode frequency \[Hz\] must be > 0"),
    ((100.0, 0.0, 1.0, 1e4), r"damping_ratio: modal damping ratio must be > 0"),
    ((100.0, 0.05, 0.0, 1e4), r"modal_mass_kg: modal mass \[kg\] must be > 0"),
    ((100.0, 0.05, 1.0, 0.0), r"fs: sample rate \[Hz\] must be > 0"),
    ((100.0, 1.0, 1.0, 1e4), r"transfer_path.damping_ratio: must be < 1, got 1"),
    ((450.0, 0.05, 1.0, 1e3), r"transfer_path.frequency_hz: mode at 450 Hz is above 0.45"),
])
def test_mode_filter_bad_input_names_the_field(args, message):
    with pytest.raises(InputError, match=message):
        mode_filter(*args)


def test_mode_just_below_the_limit_is_accepted():
    b, a = mode_filter(449.0, 0.05, 1.0, 1000.0)
    assert np.all(np.abs(np.roots(a)) < 1)


def test_transfer_path_refuses_non_finite_force():
    with pytest.raises(InputError, match="force: force history contains NaN"):
        apply_transfer_path(np.array([0.0, np.nan, 1.0]), 1e3, MODES[:1])
    with pytest.raises(InputError, match="force: force history needs at least 2"):
        apply_transfer_path(np.array([1.0]), 1e3, MODES[:1])


# ---- planet pass, seed 003 eqs 4.10-4.13 ----------------------------------------------------


def test_window_is_one_at_the_passage_and_zero_at_the_gate_edges():
    """Planet n passes at sensor + ψ_n + π/N (weight 1) and its lobe ends at ψ_n, ψ_n + 2π/N."""
    psi = np.array([0.0, 2.0, 4.1])
    sensor = 0.3
    for j in range(3):
        th = np.array([sensor + psi[j] + math.pi / 3, sensor + psi[j] + math.pi / 9])
        w = planet_pass_windows(th, 3, psi, sensor)
        assert w[j, 0] == pytest.approx(1.0, abs=1e-12)
        assert w[j, 1] == pytest.approx(0.25, abs=1e-12)  # ½(1 − cos(π/3))
    edge = planet_pass_windows(np.array([sensor + 2 * math.pi / 3 + 1e-9]), 3, psi, sensor)
    assert edge[0, 0] == 0.0


def test_printed_gate_ignores_the_planet_angles():
    """Thesis (4.12): planet j gated to [j·2π/N, (j+1)·2π/N) of θ − sensor, whatever ψ."""
    th = np.array([0.5, 2.5, 4.5])
    w = planet_pass_windows(th, 3, [0.1, 0.2, 0.3], 0.0, gating="thesis")
    for j in range(3):
        assert w[j, j] == pytest.approx(0.5 * (1 - math.cos(3 * (th[j] - [0.1, 0.2, 0.3][j]))))
        assert np.count_nonzero(w[:, j]) == 1


def test_single_planet_signal_by_hand():
    """N = 1: F(θ) = ½(1 − cos θ) Σ_h A_h cos(h Z_r (θ − ψ) + φ_h) (default sign −1)."""
    th = np.linspace(0.05, 6.2, 7)
    amp, ph, zr, psi = [1.0, 0.4], [0.0, 0.7], 23, [0.9]
    got = planet_pass_signal(th, 1, zr, amp, psi, ph)
    rel = np.mod(th - psi[0], 2 * math.pi)
    want = 0.5 * (1 - np.cos(rel)) * (np.cos(zr * (th - 0.9)) + 0.4 * np.cos(2 * zr * (th - 0.9)
                                                                              + 0.7))
    np.testing.assert_allclose(got, want, atol=1e-12)
    plus = planet_pass_signal(th, 1, zr, amp, psi, ph, mesh_phase_sign=1)
    np.testing.assert_allclose(
        plus, 0.5 * (1 - np.cos(rel)) * (np.cos(zr * (th + 0.9))
                                         + 0.4 * np.cos(2 * zr * (th + 0.9) + 0.7)), atol=1e-12)


def test_dominant_orders_rule():
    """Seed 003 §4.1: multiple of N nearest to h·Z_r — 66, 129, 195 for Z_r = 65, N = 3; for
    Z_r = 73, N = 5: 75, 145, 220, 290."""
    assert dominant_carrier_orders(65, 3) == [66, 129, 195]
    assert dominant_carrier_orders(73, 5, harmonics=4) == [75, 145, 220, 290]


@pytest.mark.parametrize("call, message", [
    (lambda: dominant_carrier_orders(0, 3), r"ring_teeth: ring tooth count must be >= 1"),
    (lambda: dominant_carrier_orders(65, 0), r"n_planets: number of planets must be >= 1"),
    (lambda: dominant_carrier_orders(65, 3, 0), r"harmonics: number of harmonics must be >= 1"),
    (lambda: planet_pass_signal(np.ones(3), 0, 65), r"n_planets: number of planets must be"),
    (lambda: planet_pass_signal(np.ones(3), 3, 0), r"ring_teeth: ring tooth count must be"),
    (lambda: planet_pass_signal(np.ones(3), 3, 65, phases=[0.0, 1.0]),
     r"phases: needs one phase per harmonic amplitude"),
    (lambda: planet_pass_signal(np.ones(3), 3, 65, mesh_phase_sign=0),
     r"mesh_phase_sign: must be -1 or \+1, got 0"),
    (lambda: planet_pass_windows(np.ones(3), 3, gating="x"),
     r"gating: must be 'centred' or 'thesis', got 'x'"),
    (lambda: planet_pass_windows(np.ones(3), 0), r"n_planets: number of planets must be"),
])
def test_planet_pass_bad_input_names_the_argument(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_graduation_error_limits():
    """A zero standard deviation needs no seed and gives the ideal edges; a pattern must stay
    strictly below half a graduation π/R (both at π/R and above it is refused)."""
    t = np.linspace(0.0, 1.0, 401)
    th = 2 * math.pi * 2 * t
    np.testing.assert_allclose(pulse_times_from_angle(t, th, 4, graduation_error=0.0),
                               np.arange(9) / 8, atol=1e-12)
    for err in (math.pi / 4, 1.2 * math.pi / 4):
        with pytest.raises(InputError, match=r"graduation_error: errors must stay below half"):
            pulse_times_from_angle(t, th, 4, graduation_error=np.array([0.0, err, 0.0, 0.0]))
    with pytest.raises(InputError, match=r"graduation_error: standard deviation must be >= 0"):
        pulse_times_from_angle(t, th, 4, graduation_error=-1e-3, seed=1)
    with pytest.raises(InputError,
                       match=r"graduation_error: graduation error pattern needs at least 4"):
        pulse_times_from_angle(t, th, 4, graduation_error=np.zeros(3))


@pytest.mark.parametrize("args, message", [
    ((np.zeros(1), np.zeros(1), 4), r"time: time vector needs at least 3 samples"),
    ((np.arange(3.0), np.arange(2.0), 4), r"angle: length 2 differs from time length 3"),
    ((np.arange(3.0)[::-1], np.arange(3.0), 4), r"time: values must be strictly increasing"),
    ((np.arange(3.0), np.ones(3), 4),
     r"angle: angle history \(shaft must turn forward; negate it otherwise\) must be strictly"),
    ((np.arange(3.0), np.arange(3.0), 0), r"pulses_per_rev: encoder resolution must be >= 1"),
])
def test_pulse_generation_bad_input_names_the_argument(args, message):
    with pytest.raises(InputError, match=message):
        pulse_times_from_angle(*args)


def test_two_modes_add_and_dict_defaults():
    """H = Σ H_i (module docstring): steady sine at 1200 Hz through the two modes of MODES has
    the amplitude |Σ H_d,i| of the bilinear closed form; a mode given by its frequency only
    takes ζ = 0.05 and m = 1 kg (the accelerance defaults)."""
    fs, f = 20_000.0, 1200.0
    t = np.arange(0, 0.4, 1 / fs)
    acc = apply_transfer_path(np.sin(2 * np.pi * f * t), fs, MODES)
    s = 2j * fs * math.tan(math.pi * f / fs)
    h = 0j
    for md in MODES:
        w = 2 * fs * math.tan(math.pi * md["frequency_hz"] / fs)
        h += s * s / (md["modal_mass_kg"] * (s * s + 2 * md["damping_ratio"] * w * s + w * w))
    assert np.abs(acc[t > 0.25]).max() == pytest.approx(abs(h), rel=0.01)
    x = np.sin(2 * np.pi * 900.0 * t[:2000])
    np.testing.assert_allclose(
        apply_transfer_path(x, fs, [{"frequency_hz": 900.0}]),
        apply_transfer_path(x, fs, [{"frequency_hz": 900.0, "damping_ratio": 0.05,
                                     "modal_mass_kg": 1.0}]), rtol=0, atol=1e-15)


def test_edges_outside_the_record_are_dropped():
    """θ = 2π t over [0, 1] s, R = 4, graduation errors ε = (−0.1, 0, 0, 0.1)·π/4: the edge
    of graduation 0 of the first turn sits at ε_0 < 0, before the record, and is dropped; the
    record holds the edges k = 1 … 4 at (k·π/2 + ε_(k mod 4))/2π s."""
    t = np.linspace(0.0, 1.0, 801)
    eps = np.array([-0.1, 0.0, 0.0, 0.1]) * math.pi / 4
    tp = pulse_times_from_angle(t, 2 * math.pi * t, 4, graduation_error=eps)
    want = (np.array([1, 2, 3, 4]) * math.pi / 2 + eps[[1, 2, 3, 0]]) / (2 * math.pi)
    np.testing.assert_allclose(tp, want, atol=1e-12)


def test_two_sample_angle_history_is_an_input_error() -> None:
    """The pulse times interpolate with a second-order speed estimate (np.gradient,
    edge_order=2): two samples are refused naming the time vector, not a numpy ValueError."""
    from geardyn.errors import InputError
    from geardyn.sensors.encoder import pulse_times_from_angle

    with pytest.raises(InputError, match="time: .*at least 3 samples"):
        pulse_times_from_angle(np.array([0.0, 1.0]), np.array([0.0, 1.0]), 10)
