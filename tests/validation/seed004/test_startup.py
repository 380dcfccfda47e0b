"""Wang 2010 (seed 004) §8.2-8.3, case 1 start-up and the case 1 / case 2 speed fluctuation
(Figs 8-1, 8-8, 8-13 to 8-16, 8-28).

Case 1 is the gearbox without bucket wheel, buckets and ore and without transmission error, from
rest (the thesis gives no initial conditions, notes §6 item 10). Its own numbers fix the load it
ran under: the ring "rotates a small amount (0.1 mm) under the action of the gearbox load"
(Fig 8-8) on k_rt = 1e10 N/m, i.e. a ring torque of ≈ 0.6 MN·m = the rated torque
T_fl·G·z_r/(z_r + z_s) = 0.56 MN·m, and the carrier runs at "approximately 5 to 6 rpm"
(Fig 8-28), below the no-load 6.36 rpm. Accelerating the unloaded gearbox needs ≈ 1 % of that
(our unloaded ring peak: 2 µm). So case 1 is run with the thesis code's "simplified high
torque" load option (ipdata(41) control ratio k = 1: T = T_fl G (n_c/(n_op/G))², the rated
torque at the rated speed)."""

from __future__ import annotations

import numpy as np
import pytest

from ._reclaimer import R_C, ZR, run

RPM = 60 / (2 * np.pi)


def _edit(case: int, from_rest: bool, load: str = "none", cpb: float = 0.0):
    def edit(d: dict) -> None:
        sim = d["planetary_dynamics"]["simulation"]
        if from_rest:
            sim["initial_speed_rpm"] = {}
        d["planetary_dynamics"]["stages"][0]["planet_bearing_damping_ns_per_m"] = cpb
        if case == 1 and load == "none":
            del sim["wheel_load"]
        elif case == 1:  # rated: ipdata(41) = 1
            sim["wheel_load"]["control_ratio"] = 1.0
        else:
            sim["wheel_load"]["schedule"] = True
            sim["wheel_load"]["inertia_schedule"] = True
    return edit


def _carrier_rpm(ds) -> tuple[np.ndarray, np.ndarray]:
    return ds.time.values, ds.v.sel(dof="carrier.u").values / R_C * RPM


@pytest.fixture(scope="module")
def case1_rated():
    return run([], 2.0, edit=_edit(1, True, "rated"))[1]


@pytest.fixture(scope="module")
def case1():
    return run([], 2.0, edit=_edit(1, True))[1]


def test_fig_8_8_ring_rotation_and_fig_8_28_speed_under_rated_load(case1_rated):
    """Fig 8-8: the ring rotates "a small amount (0.1 mm)" (one significant digit: ±0.05 mm);
    Fig 8-28: the carrier runs at "approximately 5 to 6 rpm" (steady mean, 1.5-2 s)."""
    t, rpm = _carrier_rpm(case1_rated)
    ring = np.abs(case1_rated.q.sel(dof="ring.u").values[t > 1.5]).mean()
    assert ring == pytest.approx(1e-4, abs=5e-5)  # measured 0.085 mm
    assert 5.0 <= rpm[t > 1.5].mean() <= 6.0  # measured 5.89 rpm


def test_case1_transverse_signals_steady_within_0_3_s(case1_rated):
    """§8.2 (Figs 8-1, 8-13): "The transverse signals show that the steady state ... has been
    achieved within 0.3 s", for the sun and the carrier. The transverse displacement magnitude
    |(x, y)|, averaged over one mesh period (the thesis's averaged signals are read per mesh
    pulse), enters the range it spans at steady state (1-2 s) before 0.3 s and never leaves it
    afterwards by more than that range's width: the tolerance is the signal's own steady
    fluctuation. The carrier speed is then within 2 % (and 5 %) of its final value too."""
    t, rpm = _carrier_rpm(case1_rated)
    dt = t[1] - t[0]
    w_c = rpm[t > 1.5].mean() / RPM
    n = int(round(2 * np.pi / (ZR * w_c) / dt))  # samples per mesh period
    tc = t[: len(t) - n + 1] + (n - 1) * dt / 2  # centred window times
    for body in ("sun", "carrier"):
        mag = np.hypot(case1_rated.q.sel(dof=f"{body}.x").values,
                       case1_rated.q.sel(dof=f"{body}.y").values)
        m = np.convolve(mag, np.ones(n) / n, mode="valid")
        ss = m[tc > 1.0]
        lo, hi = ss.min(), ss.max()
        first = tc[np.flatnonzero((m >= lo) & (m <= hi))[0]]
        assert first < 0.3, (body, first)  # measured: sun 0.25 s, carrier 0.23 s
        after = m[(tc > 0.3) & (tc <= 1.0)]
        assert max(after.max() - hi, lo - after.min()) < hi - lo, body
    final = rpm[t > 1.5].mean()
    for band in (0.05, 0.02):  # measured 0.25 s and 0.28 s
        outside = np.flatnonzero(np.abs(rpm - final) > band * final)
        assert t[outside[-1] + 1] < 0.3


def test_case1_fluctuation_is_the_carrier_bearing_mode_ringing(case1):
    """Root cause of our case 1 (no load) speed fluctuation: the start-up leaves the carrier
    ringing on the planet bearings, ω² = N k_pb r_c²/J_c (planets held by the meshes) =
    3·1e8·0.408²/1849.6 → 26.15 Hz; the dominant line of the carrier speed at 1-2 s is that mode
    (tolerance: one bin of the 1 s window, 1 Hz), and it decays."""
    t, rpm = _carrier_rpm(case1)
    sel = (t >= 1.0) & (t < 2.0)
    x = rpm[sel] - rpm[sel].mean()
    f = np.fft.rfftfreq(x.size, t[1] - t[0])
    a = np.abs(np.fft.rfft(x * np.hanning(x.size)))
    f_cf = np.sqrt(3 * 1e8 * 0.408**2 / 1849.6) / (2 * np.pi)
    assert f[np.argmax(a)] == pytest.approx(f_cf, abs=1.0)
    assert np.ptp(rpm[(t >= 1.5) & (t < 2.0)]) < 0.8 * np.ptp(rpm[(t >= 1.0) & (t < 1.5)])


def test_case1_fluctuation_pinned(case1):
    # regression guard (no source value): 0.16 rpm peak to peak at 1-2 s, the decaying ringing
    # of the 26 Hz carrier-on-bearings mode (test above); the thesis's ≈ 1 rpm (Fig 8-28,
    # 83 pulses per carrier revolution) is not a steady mesh vibration of its stated model: with
    # no load and no transmission error the meshes carry no mean force, so a linear model has
    # no steady excitation, and the order-1 mesh line cancels on the carrier torque by the
    # planet phasing of its Table 4-1 (docs/validation.md). Pinned to 20 %.
    t, rpm = _carrier_rpm(case1)
    assert np.ptp(rpm[t > 1.0]) == pytest.approx(0.163, rel=0.2)


def test_case1_fluctuation_vanishes_with_table_7_1_bearing_damping():
    """With the thesis's planet-bearing dampers (Table 7-1 c_px = c_py = 1e10 N·s/m) the carrier
    mode is gone and the unloaded case 1 has no fluctuation left (< 1 % of the 0.16 rpm)."""
    _, ds = run([], 2.0, edit=_edit(1, True, cpb=1e10))
    t, rpm = _carrier_rpm(ds)
    assert np.ptp(rpm[t > 1.0]) < 1.6e-3


def _rated(case: int, cpb: float = 0.0):
    def edit(d: dict) -> None:
        _edit(1, True, "rated", cpb)(d)
        if case == 2:  # carrier arm + bucket wheel + buckets, Table 6-4 (before loading)
            st = d["planetary_dynamics"]["stages"][0]
            st["carrier"]["mass_kg"], st["carrier"]["inertia_kgm2"] = 26431.0, 92926.0
    return edit


@pytest.mark.slow
def test_case2_fluctuation_ten_times_smaller_than_case1():
    """§8.3: "The signal fluctuation range is reduced by a factor of 10 times when the large mass
    and inertia (bucket wheel) is included as for case-2" — both cases under the same (rated)
    load from rest, carrier speed peak to peak at 2-3 s. Tolerance: "10" is one significant
    digit, so [5, 15). Measured 9.7 (0.0028 / 0.0003 rpm). With the Table 7-1 planet-bearing
    damper (c_px = 1e10, needed for the ch. 9 ranking) the ratio is 4.2 (0.12 / 0.027 rpm): the
    pinned planets make the carrier follow the mesh deflections, no longer inertia-limited —
    the thesis's two results do not fit one c_px in our model (docs/validation.md). The
    magnitude (≈ 1 rpm) is not reproduced (regression guard: 0.0028 rpm ± 25 %)."""
    p2p = []
    for case in (1, 2):
        _, ds = run([], 3.0, edit=_rated(case))
        t, rpm = _carrier_rpm(ds)
        p2p.append(np.ptp(rpm[t > 2.0]))
    assert 5.0 <= p2p[0] / p2p[1] < 15.0
    assert p2p[0] == pytest.approx(0.0028, rel=0.25)
