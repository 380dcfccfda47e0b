"""Speed from measured channels: analog tacho edges (MATLAB ``tachorpm`` rule) against the
closed-form edge times of a constant-acceleration run-up, hysteresis against noise, an encoder
channel's IAS, a speed profile's angle against its exact integral."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from geardyn.io import read_record
from geardyn.io.speed import angle_from_profile, pulse_times_from_signal, state_levels
from geardyn.results import channel
from tests.io.conftest import mapped_config

FS = 20_000.0
F0, ACC = 5.0, 4.0  # rev/s and rev/s² of the run-up


def _runup(duration: float = 2.0):
    t = np.arange(int(duration * FS)) / FS
    return t, 2 * np.pi * (F0 * t + 0.5 * ACC * t**2)


def _edges(k: np.ndarray, ppr: int) -> np.ndarray:
    """Times where the angle reaches 2πk/ppr: F0 t + ACC t²/2 = k/ppr."""
    return (-F0 + np.sqrt(F0**2 + 2 * ACC * k / ppr)) / ACC


def test_square_tacho_edges_within_half_a_sample():
    """A 0/5 V square train: state levels 0 and 5 V (to a histogram bin, 5 V/100), edges at
    the closed-form times to < 1/(2 fs) (the threshold crossing lies in the sample interval
    holding the edge, interpolated to its middle)."""
    ppr = 4
    t, th = _runup()
    x = np.where(np.mod(ppr * th / (2 * np.pi), 1.0) < 0.5, 5.0, 0.0)
    x[0] = 0.0
    lo, hi = state_levels(x)
    assert lo == pytest.approx(0.0, abs=0.05) and hi == pytest.approx(5.0, abs=0.05)
    tp = pulse_times_from_signal(x, FS)
    k = np.arange(tp.size)
    np.testing.assert_array_less(np.abs(tp - _edges(k, ppr)), 0.5 / FS + 1e-12)
    assert tp.size == int(np.floor(ppr * th[-1] / (2 * np.pi))) + 1


def test_hysteresis_gives_one_pulse_per_slow_noisy_edge():
    """A once-per-rev sine tacho with noise (σ = 2 % of the swing): without hysteresis the
    noise around the threshold makes extra crossings; with the default band (10 % of the
    swing, ±2.5 σ) one pulse per revolution."""
    t, th = _runup()
    rng = np.random.default_rng(1)
    x = np.sin(th - np.pi / 2) + rng.normal(0.0, 0.04, t.size)
    # rising zero crossings of −cos θ at θ = 2π(k + 1/4), k = 0, 1, … within the record
    n_edges = int(np.floor(th[-1] / (2 * np.pi) - 0.25)) + 1
    assert pulse_times_from_signal(x, FS, hysteresis=0.0).size > n_edges
    tp = pulse_times_from_signal(x, FS)
    assert tp.size == n_edges
    # a crossing on a slope s shifts by noise/s: σ/(2π F0) at the slowest edge; 4σ bound
    np.testing.assert_array_less(np.abs(tp - _edges(np.arange(tp.size) + 0.25, 1)),
                                 4 * 0.04 / (2 * np.pi * F0))


def test_profile_angle_is_the_exact_integral():
    prof = [(0.0, 600.0), (1.0, 1200.0), (3.0, 1200.0)]
    t = np.array([0.0, 0.5, 1.0, 2.0, 3.0])
    w0, a = 10.0 * 2 * np.pi, 10.0 * 2 * np.pi  # rad/s, rad/s²
    exact = np.array([0.0, w0 * 0.5 + a * 0.125, w0 + a * 0.5, w0 + a * 0.5 + 2 * w0,
                      w0 + a * 0.5 + 4 * w0])
    np.testing.assert_allclose(angle_from_profile(t, prof), exact, rtol=1e-12)


def test_tacho_and_encoder_channels_of_a_record(tmp_path, sim_run):
    """Analog tacho (60 pulses/rev) and encoder (500 lines) channels of the sun in a CSV at
    20 kHz: the shaft angle of the record follows the simulated sun angle (to 2e-3 rad), the
    encoder IAS has the simulated mean speed (0.1 %), links turning with the sun get their
    kinematic ratio (carrier: 19/(19 + 83), seed 000 eq 5)."""
    from tests.io.conftest import analog_tacho

    _, ds = sim_run
    t = np.arange(int(2.0 * FS)) / FS
    th = np.interp(t, ds.time.values, ds.angle.sel(shaft="sun").values)
    acc = np.sin(2 * np.pi * 300 * t)
    pd.DataFrame({"t": t, "acc": acc, "tacho": analog_tacho(t, th, 60),
                  "enc": analog_tacho(t, th, 500)}).to_csv(tmp_path / "r.csv", index=False)
    extra = ('file_units = "V"\n'
             '[[measurement.channels]]\nname = "sun_tacho"\nsource = "tacho"\nkind = "tacho"\n'
             'shaft = "sun"\npulses_per_rev = 60\n'
             '[[measurement.channels]]\nname = "sun_enc"\nsource = "enc"\nkind = "encoder"\n'
             'shaft = "sun"\npulses_per_rev = 500\n')
    cfg = mapped_config(tmp_path, "acc", extra)
    rec = read_record(tmp_path / "r.csv", cfg=cfg)
    assert rec.attrs["speed_source"] == "tacho 'sun_tacho'"
    ang = rec.angle.sel(shaft="sun").values
    true = np.interp(rec.time.values, ds.time.values, ds.angle.sel(shaft="sun").values)
    off = true[0] - ang[0]  # the first detected pulse is the record's angle origin
    assert np.max(np.abs(ang + off - true)) < 2e-3
    carrier = rec.angle.sel(shaft="carrier").values
    np.testing.assert_allclose(carrier - carrier[0], (ang - ang[0]) * 19 / 102, rtol=1e-9)
    enc = channel(rec, "sun_enc")
    assert enc.kind == "encoder" and enc.sampling == "angle" and enc.units == "rad/s"
    mean_true = (th[-1] - th[0]) / (t[-1] - t[0])
    assert np.mean(enc.values) == pytest.approx(mean_true, rel=1e-3)


def test_missing_pulse_is_restored_and_jitter_kept():
    """Pulses of the run-up with 1 % jitter (of an interval) and pulses 7 and 20–21 missing:
    three pulses inserted evenly, within 10 % of an interval of the true ones (the neighbours'
    jitter, 3σ each, plus the run-up's change of speed over the gap, ≈ 8 % over three
    intervals); every detected pulse is kept as it was."""
    from geardyn.io.speed import repair_missing_pulses

    true = _edges(np.arange(40), 4)
    rng = np.random.default_rng(3)
    jit = true + 0.01 * np.gradient(true) * rng.standard_normal(true.size)
    kept = np.delete(jit, [7, 20, 21])
    tp, fixed = repair_missing_pulses(kept)
    assert tp.size == true.size and len(fixed) == 2
    ins = np.array([7, 20, 21])
    np.testing.assert_array_less(np.abs(tp - true)[ins], 0.1 * np.gradient(true)[ins])
    np.testing.assert_array_equal(np.delete(tp, ins), kept)
    same, none = repair_missing_pulses(jit)
    assert none == [] and np.array_equal(same, jit)
