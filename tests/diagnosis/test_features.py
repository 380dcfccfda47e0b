"""Features per component on synthetic channels with known faults.

Seed 002 two-stage transmission (input 31/53 intermediate 42/55 output, intermediate shaft
counter-rotating, ratio −31/53): an accelerometer signal built from the two meshes in the
angles of their shafts, under a ±2 % speed fluctuation, with (a) a local fault on the 42-tooth
wheel (50 % amplitude modulation of its mesh, Gaussian of σ = 1.5 tooth pitches), (b) an
outer-race fault on the output ball bearing (impulses at BPFO exciting a 3 kHz resonance,
Randall & Antoni 2011). The diagnosis must point at the right wheel (not at the 53-tooth
wheel on the same shaft) and at the right bearing line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import geardyn
from geardyn.diagnosis.components import machine_components
from geardyn.diagnosis.features import COLUMNS, extract_features
from geardyn.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FS = 8192.0
F0 = 1000.0 / 60.0  # input shaft [rev/s]
R_INT = 31 / 53
R_OUT = 31 / 53 * 42 / 55


@pytest.fixture(scope="module")
def comps():
    return machine_components(geardyn.load_config(EXAMPLES / "seed002_transmission.toml"), "input")


def transmission_signal(wheel_fault: bool, bearing_fault: bool, seed: int, duration=2.6):
    t = np.arange(int(duration * FS)) / FS
    theta = 2 * np.pi * F0 * (t + 0.02 / np.pi * np.sin(np.pi * t))  # speed f0(1 + 0.02 cos πt)
    phi_int = R_INT * theta  # |angle| of the counter-rotating intermediate shaft
    high = (1 + 0.05 * np.cos(theta)) * (np.cos(31 * theta) + 0.3 * np.cos(62 * theta + 1))
    m42 = 1 + 0.05 * np.cos(phi_int + 0.7)
    if wheel_fault:
        sigma = 1.5 * 2 * np.pi / 42
        d = np.mod(phi_int, 2 * np.pi) - np.pi
        m42 = m42 + 0.5 * np.exp(-0.5 * (d / sigma) ** 2)
    low = m42 * (0.8 * np.cos(42 * phi_int + 0.3) + 0.2 * np.cos(84 * phi_int))
    x = high + low
    if bearing_fault:
        bpfo = 5.5 * (1 - 12.7 / 80) * R_OUT  # orders of the input (Harris, fixed outer ring)
        events = np.interp(
            np.arange(1, theta[-1] * bpfo / (2 * np.pi)), theta * bpfo / (2 * np.pi), t
        )
        tt = np.arange(0, 0.02, 1 / FS)
        h = np.exp(-tt * 800) * np.sin(2 * np.pi * 3000 * tt)
        imp = np.zeros_like(t)
        imp[np.round(events * FS).astype(int)] = 1.0
        x = x + 1.5 * np.convolve(imp, h)[: t.size]
    x = x + np.random.default_rng(seed).normal(0, 0.1, t.size)
    return x, t, theta


def test_table_layout_and_artefacts(comps):
    x, t, th = transmission_signal(False, False, 1)
    f = extract_features(x, t, th, comps, channel="acc", units="m/s^2", n_blocks=4)
    assert list(f.table.columns) == COLUMNS
    assert set(f.table["kind"]) == {"shaft", "wheel", "bearing"}
    assert set(f.table["block"]) == {0, 1, 2, 3}
    assert (f.table["channel"] == "acc").all()
    da = f.tsa["intermediate"]
    assert da.attrs["units"] == "m/s^2" and da["angle"].attrs["units"] == "deg"
    # the order spectrum shows the high mesh at order 31 with amplitude 1 (Hann-corrected,
    # ±5 %) and the low mesh at 42·31/53 = 24.566 (not on a bin: only located)
    spec = f.order_spectrum
    assert float(spec.sel(order=31, method="nearest")) == pytest.approx(1.0, rel=0.05)
    near = spec.sel(order=slice(24, 25.2))
    o_low = float(near["order"][int(np.argmax(near.values))])
    assert o_low == pytest.approx(42 * 31 / 53, abs=0.05)
    assert f.envelope_spectrum.dims == ("order",)
    assert f.kurtogram is not None and f.band is not None
    assert f.markers is not None and {"label", "kind", "order"} <= set(f.markers.columns)


def test_wheel_fault_on_a_shared_counter_rotating_shaft(comps):
    """The 42-tooth wheel shares the intermediate shaft (ratio −31/53) with the 53-tooth
    wheel. Median over 4 blocks, measured over seeds 2, 3, 7, 8: z42 SER 0.082–0.085 healthy →
    0.21–0.22 faulty (×2.5), sideband kurtosis 2.4–2.6 → 4.9–5.1 (×1.9); z53 SER 0.033–0.039 →
    0.040–0.046 (+15 %: the tail of the 42 wheel's sideband family, σ ≈ 4 orders, reaches
    53 − 3), sideband kurtosis 2.6–3.1 both; shaft FM4 2.9–3.0 → 7.6–7.9. Asserted: z42 SER
    ≥ 2× and kurtosis ≥ 1.6× the healthy mean (3 seeds, as a baseline would); z53 within
    30 %; z42's relative rise ≥ 4× z53's."""
    base = [extract_features(*transmission_signal(False, False, s), comps) for s in (2, 7, 8)]
    faulty = extract_features(*transmission_signal(True, False, 3), comps).summary()

    def val(s, comp, ind):
        if s is None:  # healthy mean over the baseline seeds
            return float(np.mean([val(b.summary(), comp, ind) for b in base]))
        return float(s[(s.component == comp) & (s.indicator == ind)]["value"].iloc[0])

    healthy = None

    def rise(comp, ind):
        return val(faulty, comp, ind) / val(healthy, comp, ind)

    assert rise("intermediate/z42", "SER") >= 2.0
    assert rise("intermediate/z42", "sideband_kurtosis") >= 1.6
    for ind in ("SER", "sideband_kurtosis"):
        assert rise("intermediate/z53", ind) == pytest.approx(1.0, abs=0.3)
        assert rise("intermediate/z42", ind) - 1 >= 4 * abs(rise("intermediate/z53", ind) - 1)
    assert val(healthy, "intermediate", "FM4") < 3.6
    assert val(faulty, "intermediate", "FM4") > 6.0
    # the input shaft (other shaft) does not see it in its TSA
    assert val(faulty, "input", "FM4") < 3.6


def test_outer_race_fault_on_the_right_bearing(comps):
    """BPFO of the output ball bearing = 5.5(1 − 12.7/80)·(31/53)(42/55) = 2.0666 input orders.
    Squared-envelope line ratio (peak/local median, mean of harmonics 1–3) in the kurtogram
    band (measured 160–288 orders, around the 3 kHz = 180 orders resonance): healthy 1.67
    (noise), faulty 44.9 measured; asserted ≥ 10× healthy, the largest BPFO ratio of all
    bearings, and a band containing the resonance."""
    healthy = extract_features(*transmission_signal(False, False, 4), comps).summary()
    faulty = extract_features(*transmission_signal(False, True, 5), comps).summary()
    fb = faulty[faulty.indicator == "BPFO"].set_index("component")["value"]
    hb = healthy[healthy.indicator == "BPFO"].set_index("component")["value"]
    assert fb["output ball"] >= 10 * hb["output ball"]
    assert fb.idxmax() == "output ball"
    lo, hi = extract_features(*transmission_signal(False, True, 5), comps).band
    assert lo < 3000 / F0 < hi


def test_angle_sampled_channel_is_interpolated_in_angle(comps):
    """An encoder-like channel: one sample per 1/256 rev of the input, at the (non-uniform)
    instants of a varying speed; a 3-order IAS modulation of amplitude 2 reads 2 ± 2 %."""
    th = 2 * np.pi * np.arange(256 * 40) / 256
    speed = 2 * np.pi * F0 * (1 + 0.1 * np.sin(th / 7))
    t = np.concatenate([[0.0], np.cumsum(np.diff(th) / (0.5 * (speed[1:] + speed[:-1])))])
    x = 100 + 2.0 * np.cos(3 * th)
    f = extract_features(x, t, th, comps, n_blocks=2)
    assert f.samples_per_rev == 256
    assert float(f.order_spectrum.sel(order=3, method="nearest")) == pytest.approx(2.0, rel=0.02)


def test_bad_input_is_named(comps):
    x, t, th = transmission_signal(False, False, 6, duration=0.5)
    with pytest.raises(InputError, match="ref_angle: the reference angle must be strictly"):
        extract_features(x, t, np.where(t < 0.2, th, th[::-1]), comps)
    with pytest.raises(InputError, match="x: .*NaN"):
        extract_features(np.full_like(x, np.nan), t, th, comps)
    with pytest.raises(InputError, match="ref_angle: the record spans 0.8.* needs ≥ 1"):
        extract_features(x[:400], t[:400], th[:400], comps)
    with pytest.raises(InputError, match="n_blocks"):
        extract_features(x, t, th, comps, n_blocks=0)
    with pytest.raises(InputError, match="envelope_band"):
        extract_features(x, t, th, comps, envelope_band=(10.0, 5.0))
