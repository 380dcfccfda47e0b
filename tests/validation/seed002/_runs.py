"""Seed 002 §3.5 runs of the FE transmission (examples/seed002_transmission.toml), shared by
the validation tests: 20 revolutions, 360 → 430 rpm (the seed's [360 – 430 rpm / 20 rev])."""

from __future__ import annotations

import math
from functools import cache
from pathlib import Path

import numpy as np
from scipy.signal import butter, filtfilt

from geardyn.bearings.frequencies import bearing_frequencies
from geardyn.config.loader import load_config, parse_config
from geardyn.models.transmission.assembly import build_model, static_equilibrium
from geardyn.models.transmission.simulate import simulate
from geardyn.sensors.encoder import simulate_ias
from geardyn.signal.resample import resample_ias_to_angle
from geardyn.signal.spectra import order_spectrum

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "seed002_transmission.toml"
PPR = 1000
BPFO = bearing_frequencies(1.0, 0.0, 11, 0.0127, 0.080).bpfo  # output ball bearing, ev/rev
HIGH_MESH = 31 * (55 / 42) * (53 / 31)  # high-stage mesh order on the output shaft (69.40)
ROOT_CHORD = 6.68e-3  # 55-tooth wheel root chord (docs/stiffness.md); crack % of it
#: seed 002 §3.5.3: 15 % (normal) and 25 % (deep) of the tooth thickness; spall 100 µm deep on
#: the pitch circle (82.5 mm), a third of the height, half the face at its centre
CASES = ("healthy", "bearing_spall", "crack15", "crack25", "gear_spall")


def _data() -> dict:
    return load_config(EXAMPLE).model_dump(exclude_none=True)


def _variant(case: str, start_rpm: float = 360.0, end_rpm: float = 430.0) -> dict:
    d = _data()
    d["transmission"] = {**d["transmission"]}
    d["transmission"]["speed_law"] = {
        **d["transmission"]["speed_law"], "start_rpm": start_rpm, "end_rpm": end_rpm,
    }
    gg = [dict(g) for g in d["gear_geometry"]]
    low = next(g for g in gg if g["pair"] == "low")
    if case.startswith("crack"):
        frac = int(case[5:]) / 100
        low["cracks"] = [{"gear": "b", "tooth": 0, "depth_m": frac * ROOT_CHORD,
                          "angle_deg": 45.0}]
    elif case == "gear_spall":
        low["spalls"] = [{"gear": "b", "tooth": 0, "radius_m": 0.0825,
                          "radial_width_m": 0.0029, "depth_m": 100e-6,
                          "axial_position_m": 0.0125, "axial_length_m": 0.0125}]
    elif case == "bearing_spall":
        cfg = parse_config(d)
        m = build_model(cfg)
        q = static_equilibrium(m, m.load_torque)
        nd = m.node_of("output", 1)
        ang = math.degrees(math.atan2(q[6 * nd + 1], q[6 * nd]))
        brs = [dict(b) for b in d["transmission"]["bearings"]]
        assert brs[0]["name"] == "output ball"
        brs[0]["outer_spall"] = {"angle_deg": ang, "angular_length_deg": 360.0 / 11 / 3,
                                 "depth_m": 100e-6}
        d["transmission"]["bearings"] = brs
    d["gear_geometry"] = gg
    return d


@cache
def ias_angle(case: str, start_rpm: float = 360.0, end_rpm: float = 430.0) -> np.ndarray:
    """Low-speed shaft IAS (rad/s) through the 1000 ppr / 80 MHz encoder, resampled at 1000
    points per revolution (seed 002 eq 1), first revolution dropped."""
    ds = simulate(parse_config(_variant(case, start_rpm, end_rpm)), revolutions=20.0)
    th = ds.angle.sel(shaft="output").values
    m = simulate_ias(ds.time.values, th - th[0], pulses_per_rev=PPR, f_clock=80e6)
    return resample_ias_to_angle(m.angle, m.ias, PPR)[PPR:]


def detrended(case: str) -> np.ndarray:
    """IAS over whole revolutions minus its quadratic trend (the speed ramp), rad/s."""
    w = ias_angle(case)
    n = (w.size // PPR) * PPR
    x = np.arange(n)
    return w[:n] - np.polyval(np.polyfit(x, w[:n], 2), x)


def spectrum(case: str) -> tuple[np.ndarray, np.ndarray]:
    """(orders [events/rev], amplitude [rad/s]) of the detrended low-speed shaft IAS (Hann)."""
    sp = order_spectrum(detrended(case), PPR)
    return sp.order.values, sp.values


def mean_difference(case: str, cutoff_order: float = 150.0) -> np.ndarray:
    """Faulty − healthy IAS (rad/s) low-passed at ``cutoff_order`` (4th-order Butterworth,
    zero phase) and averaged over revolutions 3-19: one revolution, PPR samples (Fig 20)."""
    d = detrended(case) - detrended("healthy")
    b, a = butter(4, cutoff_order / (PPR / 2))
    return filtfilt(b, a, d).reshape(-1, PPR)[2:].mean(axis=0)


def peak(o: np.ndarray, a: np.ndarray, order: float) -> float:
    """Amplitude at ``order`` (max over ±1 bin)."""
    i = int(np.argmin(np.abs(o - order)))
    return float(a[i - 1 : i + 2].max())
