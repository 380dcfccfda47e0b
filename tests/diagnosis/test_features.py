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
    53 − 3), sideband kurtosis 2.6–3.1 both; shaft FM4 2.9–3.0 → 6.6–6.9 (combination tones
    a·53 + b·42, |a| + |b| ≤ 12, counted as regular meshing). Asserted: z42 SER
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
    assert val(faulty, "intermediate", "FM4") > 5.0
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


# ---------------------------------------------------------------- planetary, ring sensor
ZR, ZP, NPL = 83, 32, 3  # seed 004 Table 6-2


def ring_signal(seed: int, planet_fault: int | None = None, ring_fault: bool = False):
    """Ring-accelerometer signal of the seed 004 stage (sun reference, carrier = 19/102 of
    it): each planet's ring mesh (harmonics 1, 2; sequential phasing Z_r·ψ_n) weighted by its
    planet-pass window (seed 003 eqs 4.10–4.12 as the simulator's ring sensor applies them,
    :func:`geardyn.sensors.channels.ring_sensor_windows`: planet n at θ_c + ψ_n faces the
    sensor at frame angle 0). A planet fault modulates that planet's mesh by 50 % (Gaussian,
    σ = 1.5 tooth pitches) once per planet revolution relative to the carrier (mesh count mod
    Z_p); a ring fault doubles the mesh of whichever planet is at the faulty ring tooth, at
    35° of the frame (seen by the sensor with lobe weight 0.37, outside the ±28° planet
    windows). 24 carrier revolutions, 512 samples per sun revolution, white noise σ = 0.1."""
    from geardyn.sensors.channels import ring_sensor_windows

    th_s = 2 * np.pi * np.arange(int(24 * 102 / 19 * 512)) / 512
    th_c = 19 / 102 * th_s
    psi = 2 * np.pi * np.arange(NPL) / NPL
    w = ring_sensor_windows(th_c, psi, 0.0)
    x = np.zeros_like(th_s)
    for n in range(NPL):
        m = np.ones_like(th_s)
        if n == planet_fault:
            d = np.mod(ZR / ZP * th_c - 1.0, 2 * np.pi) - np.pi
            m += 0.5 * np.exp(-0.5 * (d / (1.5 * 2 * np.pi / ZP)) ** 2)
        if ring_fault:
            d = np.mod(th_c + psi[n] - np.radians(35.0) + np.pi, 2 * np.pi) - np.pi
            m += 1.0 * np.exp(-0.5 * (d / (1.5 * 2 * np.pi / ZR)) ** 2)
        ph = ZR * (th_c + psi[n])
        x += w[n] * m * (np.cos(ph) + 0.3 * np.cos(2 * ph + 0.4))
    x += np.random.default_rng(seed).normal(0, 0.1, x.size)
    return x, th_s / np.pi, th_s  # sun at 0.5 rev/s


@pytest.fixture(scope="module")
def seed004():
    return machine_components(geardyn.load_config(EXAMPLES / "planetary_reclaimer.toml"), "sun")


def _fm4(comps, sig):
    f = extract_features(*sig, comps, ring_stage="planetary", n_blocks=4, planet_windows=True)
    s = f.summary()
    return s[s.indicator == "FM4"].set_index("component")["value"], f


def test_planet_window_tsa_localises_the_faulty_planet(seed004):
    """McFadden's window technique on the ring channel: measured FM4 (median of 4 blocks of
    6 carrier revolutions) healthy 2.97–3.52 for every planet; with a fault on planet 2
    (index 1) 4.91 on planet 2, the other planets unchanged (3.15–3.52), the sun (own-angle
    TSA) 2.90, the ring 3.06. Asserted: planet 2 > 4.2, every other planet/sun/ring < 3.9."""
    healthy, fh = _fm4(seed004, ring_signal(3))
    faulty, ff = _fm4(seed004, ring_signal(3, planet_fault=1))
    planets = [c.name for c in seed004.of_kind("planet")]
    assert all(healthy[p] < 3.9 for p in planets)
    assert faulty[planets[1]] > 4.2
    for other in (planets[0], planets[2], "planetary.sun", "planetary.ring"):
        assert faulty[other] < 3.9
    assert ff.tsa[planets[1]].attrs["method"].startswith("planet-window TSA")
    assert ff.tsa[planets[1]].size % ZP == 0  # Z_p ring-mesh periods of whole samples
    assert not ff.notes


def _envelope_peak_deg(da, teeth=None) -> float:
    """Angle [deg] of the maximum of the smoothed envelope of a TSA (mean removed), or of its
    difference signal if ``teeth`` are given."""
    from scipy.ndimage import uniform_filter1d
    from scipy.signal import hilbert

    from geardyn.signal import difference_signal

    v = da.values - da.values.mean()
    if teeth is not None:
        v = difference_signal(v, teeth)
    e = uniform_filter1d(np.abs(hilbert(v)), max(1, v.size // 36), mode="wrap")
    return float(da["angle"].values[int(np.argmax(e))])


def test_tsa_angles_are_own_angles_whatever_the_record_start(comps, seed004):
    """The TSA's angle coordinate is the component's own angle: the 42-tooth wheel's fault
    at intermediate angle 180° (|ratio|·θ_in, counter-rotating shaft) and planet 2's at
    planet-frame angle (1 + π) rad = 237.3° (mesh count Z_r·θ_c/2π mod Z_p) are found there
    (envelope of the shaft's difference signal / of the planet TSA; measured 181.4° and
    239.1°; ±1 tooth pitch: 8.6° and 11.3°), also when the record starts
    at an arbitrary angle (samples dropped)."""
    x, t, th = transmission_signal(True, False, 3)
    for cut in (0, 1234):
        f = extract_features(x[cut:], t[cut:], th[cut:], comps)
        peak = _envelope_peak_deg(f.tsa["intermediate"], (53, 42))
        assert peak == pytest.approx(180.0, abs=8.6)
    x, t, th = ring_signal(3, planet_fault=1)
    p2 = seed004.of_kind("planet")[1].name
    for cut in (0, 777):
        f = extract_features(
            x[cut:], t[cut:], th[cut:], seed004, ring_stage="planetary", planet_windows=True
        )
        assert _envelope_peak_deg(f.tsa[p2]) == pytest.approx(np.degrees(1 + np.pi), abs=11.3)


def test_ring_fault_seen_in_the_carrier_angle_tsa(seed004):
    """Ring fault at 35°: measured ring FM4 3.03 healthy → 4.58, planets 3.16–3.63 (planet 1,
    whose windows are nearest the fault, is 3.6 healthy too), sun 2.93 (the planet-pass orders
    k·Z_r → multiples of N are counted as regular meshing, so the healthy ring's FM4 stays
    Gaussian-like). Asserted: ring > 4.0 (healthy < 3.6), planets and sun < 3.9."""
    healthy, _ = _fm4(seed004, ring_signal(4))
    faulty, _ = _fm4(seed004, ring_signal(5, ring_fault=True))
    assert healthy["planetary.ring"] < 3.6
    assert faulty["planetary.ring"] > 4.0
    for c in seed004.of_kind("planet", "sun"):
        assert faulty[c.name] < 3.9


# ---------------------------------------------------------------- result layout
def _result(x, t, theta, with_tacho: bool):
    """A minimal dataset in the geardyn result layout (docs/results.md): shafts input,
    intermediate, output with their angles; an accelerometer on the input; a once-per-rev
    tacho on the intermediate shaft (counter-rotating) if asked."""
    import xarray as xr

    angles = np.stack([theta, -R_INT * theta, R_OUT * theta], axis=1)
    ds = xr.Dataset(
        {"angle": (("time", "shaft"), angles, {"units": "rad"})},
        coords={"time": ("time", t, {"units": "s"}), "shaft": ["input", "intermediate", "output"]},
        attrs={"geardyn_layout": "geardyn.result/1", "reference_shaft": "input"},
    )
    ds["sensors.acc"] = xr.DataArray(
        x,
        dims=("sensors.acc.time",),
        coords={"sensors.acc.time": t},
        attrs={
            "sensor_kind": "accelerometer",
            "units": "m/s^2",
            "sampling": "time",
            "shaft": "input",
            "sample_rate_hz": FS,
            "location": "bearing 'input ball'",
        },
    )
    if with_tacho:
        phi = R_INT * theta
        pulses = np.interp(2 * np.pi * np.arange(1, int(phi[-1] / (2 * np.pi)) + 1), phi, t)
        ds["sensors.tacho"] = xr.DataArray(
            pulses,
            dims=("sensors.tacho.pulse",),
            attrs={
                "sensor_kind": "tacho",
                "units": "s",
                "sampling": "events",
                "shaft": "intermediate",
                "pulses_per_rev": 1,
            },
        )
    return ds


def test_features_from_result_with_and_without_tacho():
    """Both reference sources (tacho on the counter-rotating intermediate shaft, divided by
    its ratio; the result's input angle) give the same indicators on the faulty-wheel signal:
    measured intermediate FM4 6.71 (result angle) and 6.76 (tacho, 0.3 s skipped; the
    tacho also crops the record to its pulse span, so the blocks differ); asserted within 10 %.
    skip_s drops 0.3 s ≈ 5 input revolutions."""
    from geardyn.diagnosis.features import features_from_result

    cfg = geardyn.load_config(EXAMPLES / "seed002_transmission.toml")
    x, t, th = transmission_signal(True, False, 3)
    a = features_from_result(_result(x, t, th, False), cfg, "acc")
    b = features_from_result(_result(x, t, th, True), cfg, "acc", skip_s=0.3)
    assert a.channel == "acc" and a.units == "m/s^2" and a.reference == "input"
    fa = float(np.median(a.values("intermediate", "FM4")))
    fb = float(np.median(b.values("intermediate", "FM4")))
    assert fa > 5.0
    assert fb == pytest.approx(fa, rel=0.1)
    assert b.revolutions < a.revolutions - 0.3 * F0 * 0.9
    with pytest.raises(InputError, match="channel: 'tacho' holds pulse times"):
        features_from_result(_result(x, t, th, True), cfg, "tacho")
    with pytest.raises(InputError, match="channel: 'nope' not found"):
        features_from_result(_result(x, t, th, True), cfg, "nope")


def test_reference_residuals_against_healthy_records(comps):
    """Block TSAs minus the healthy mean TSA of the same blocks (leave-one-out for the
    baselines): the healthy residual is the averaging noise, Gaussian (RR_kurtosis 3; measured
    2.6–3.9), the 42-tooth wheel fault leaves its local modulation: measured per block,
    intermediate RR_kurtosis 13.5–15.4, wheel z42 6.8–7.6, wheel z53 2.8–3.0, input shaft
    2.9–3.3 (the fault is not synchronous with it). Asserted (medians): baseline blocks within
    3 ± 1, faulty intermediate > 8, z42 > 5, z53 and input < 3.6."""
    from geardyn.diagnosis.features import with_reference_residuals

    base = [extract_features(*transmission_signal(False, False, s), comps) for s in (2, 7, 8)]
    rec = extract_features(*transmission_signal(True, False, 3), comps)
    base2, rec2 = with_reference_residuals(base, rec)
    for f in base2:
        k = f.values("intermediate", "RR_kurtosis")
        assert k.size == 4 and np.all(np.abs(k - 3) < 1.0)
    assert np.median(rec2.values("intermediate", "RR_kurtosis")) > 8.0
    assert np.median(rec2.values("intermediate/z42", "RR_kurtosis")) > 5.0
    assert np.median(rec2.values("intermediate/z53", "RR_kurtosis")) < 3.6
    assert np.median(rec2.values("input", "RR_kurtosis")) < 3.6
    assert list(rec2.table.columns) == COLUMNS
    assert len(rec.table) < len(rec2.table)  # new objects, the input is untouched
    with pytest.raises(InputError, match="at least 2 healthy records"):
        with_reference_residuals(base[:1], rec)


def test_long_record_path_gives_the_same_gear_indicators(comps, monkeypatch):
    """A reference grid longer than SEGMENT_MAX is streamed (stretch-by-stretch resampling,
    revolution-batch statistics, segment-averaged envelope spectra): the TSA indicators are
    those of the whole-record path (1e-5: float32 channel); the bearing line ratios rest on
    segments of 24 revolutions averaged instead of one block of 49 and still point at the
    outer race of the output ball bearing."""
    import geardyn.diagnosis.features as features

    x, t, th = transmission_signal(False, True, 5, duration=6)
    whole = extract_features(x, t, th, comps, n_blocks=2)
    monkeypatch.setattr(features, "SEGMENT_MAX", 32768)
    long = extract_features(x.astype(np.float32), t, th, comps, n_blocks=2)
    assert long.envelope_spectrum.attrs["segment_revolutions"] == 24
    assert long.envelope_spectrum.attrs["segments"] == 4
    m = whole.table.merge(long.table, on=["component", "kind", "indicator", "block"])
    gear = m[m["kind"] != "bearing"]
    assert len(gear) == len(whole.table[whole.table["kind"] != "bearing"])
    # float32 storage of the channel: 6e-8 relative
    np.testing.assert_allclose(gear["value_y"], gear["value_x"], rtol=1e-5)
    b = long.summary()
    b = b[b["indicator"] == "BPFO"].set_index("component")["value"]
    assert b.idxmax() == "output ball"
    assert long.order_spectrum is not None and long.samples_per_rev == whole.samples_per_rev
