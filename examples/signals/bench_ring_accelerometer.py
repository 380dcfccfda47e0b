"""Synthetic ring-accelerometer record of the Hammami 2015 back-to-back bench (example input for
``geardyn analyze``).

Motor (sun shaft) at 1498.5 rpm; carrier at 16/81 of it; test-ring accelerometer seeing the
planet-pass modulated ring mesh (Hammami 2015, eqs 4.10-4.13 with the gating fix), a small sun-shaft
once-per-rev component, white noise and a 16-bit ADC. A once-per-rev tacho on the motor shaft
is stored with the signal. Usage::

    python examples/signals/bench_ring_accelerometer.py OUT.nc
    geardyn analyze OUT.nc --config examples/hammami_back_to_back.toml --speed motor=1498.5
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from geardyn.sensors import accelerometer, planet_pass_signal, tacho_pulse_times
from geardyn.signal_io import write_signal_netcdf

RPM = 1498.5
FS = 8192.0
DURATION = 8.0  # s


def make(path: str | Path, seed: int = 0) -> Path:
    t = np.arange(int(FS * DURATION)) / FS
    theta_motor = 2 * np.pi * RPM / 60 * t
    theta_carrier = theta_motor * 16 / 81  # Hammami 2015, §4.1: sun → carrier 81/16
    x = planet_pass_signal(theta_carrier, 3, 65, amplitudes=[1.0, 0.5, 0.3])
    x += 0.05 * np.cos(theta_motor + 0.4)
    y = accelerometer(x, noise_rms=0.1, bits=16, seed=seed)
    tp = tacho_pulse_times(t, theta_motor)
    return write_signal_netcdf(path, y, FS, name="ring_accel", units="m/s2", pulse_times=tp)


if __name__ == "__main__":
    path = make(sys.argv[1] if len(sys.argv) > 1 else "bench_ring_accelerometer.nc")
    print(f"wrote {path}: {DURATION:g} s of a ring accelerometer (m/s2) at {FS:g} Hz with a "
          f"once-per-revolution tacho, motor at {RPM:g} rpm (back-to-back bench, Hammami 2015)")
    print(f"next: geardyn analyze {path} --config examples/hammami_back_to_back.toml "
          f"--speed motor={RPM:g} --out bench_report/")
