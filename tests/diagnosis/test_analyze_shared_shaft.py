"""`geardyn analyze` on the issue's shared-shaft case: a faulty 19-tooth pinion on the shaft of
a 71-tooth wheel. The difference signal removes every mesh of the shaft (Zakrajsek et al. 1993
definitions applied to each mesh), so the shaft's FM4 flags the fault (the old single-mesh
difference kept the 71 mesh: FM4 ≈ 1.5, a sinusoid's kurtosis), and the wheel indicators on
each wheel's own sidebands point at the 19-tooth pinion, not at the 71-tooth wheel."""

from __future__ import annotations

import numpy as np
import pandas as pd
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.signal_io import write_signal_netcdf

CONFIG = """
name = "two wheels on one shaft"
frame = "housing"
links = ["housing", "in", "mid", "out"]

[[parallel]]
name = "first"
a = { link = "in", teeth = 23 }
b = { link = "mid", teeth = 71 }

[[parallel]]
name = "second"
a = { link = "mid", teeth = 19 }
b = { link = "out", teeth = 57 }

[input_speeds_rpm]
in = 1500.0
"""


def _signal(fault: bool, fs: float = 20000.0, revs: int = 48, seed: int = 0):
    f_mid = 1500.0 * 23 / 71 / 60.0
    t = np.arange(int(revs / f_mid * fs)) / fs
    th = 2 * np.pi * f_mid * t
    x = np.cos(71 * th) + 0.4 * np.cos(142 * th + 0.3) + 0.8 * np.cos(19 * th + 1.0)
    if fault:  # a cracked 19-tooth pinion tooth: the 19 mesh's amplitude drops once per rev
        phase = np.mod(th, 2 * np.pi)
        x -= 0.8 * np.cos(19 * th + 1.0) * 0.6 * np.exp(-0.5 * ((phase - 2.0) / 0.08) ** 2)
    x += np.random.default_rng(seed).normal(0, 0.02, t.size)
    return x, fs, f_mid * 60.0


def _analyze(tmp_path, fault):
    cfg = tmp_path / "shared.toml"
    cfg.write_text(CONFIG)
    x, fs, rpm = _signal(fault)
    sig = tmp_path / f"x{int(fault)}.nc"
    write_signal_netcdf(sig, x, fs, units="m/s^2")
    out = tmp_path / f"rep{int(fault)}"
    r = CliRunner().invoke(app, ["analyze", str(sig), "-c", str(cfg), "--speed", f"mid={rpm}",
                                 "--out", str(out)])
    assert r.exit_code == 0, r.output
    return pd.read_csv(out / "indicators.csv").set_index("component"), out


def test_shared_shaft_fault_on_the_19_tooth_pinion(tmp_path):
    healthy, _ = _analyze(tmp_path, False)
    faulty, out = _analyze(tmp_path, True)
    assert (out / "tsa_mid.png").is_file() and (out / "tsa_in.png").is_file()
    # every mesh of 'mid' removed: healthy difference signal is noise (FM4 ≈ 3), the fault
    # makes it impulsive
    assert abs(healthy.loc["mid", "FM4"] - 3.0) < 0.6
    assert faulty.loc["mid", "FM4"] > 6.0
    wheels = [c for c in faulty.index if isinstance(c, str) and c.startswith("mid/")]
    z19 = next(c for c in wheels if c.endswith("z19"))
    z71 = next(c for c in wheels if c.endswith("z71"))
    rise = {c: faulty.loc[c, "SER"] / healthy.loc[c, "SER"] for c in (z19, z71)}
    assert rise[z19] > 5.0 * rise[z71], rise
    assert rise[z71] < 1.5
