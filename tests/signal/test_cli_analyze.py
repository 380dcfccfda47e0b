"""``geardyn analyze`` end to end on the example signal, and signal I/O round trips."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.errors import InputError
from geardyn.signal_io import read_pulse_times, read_signal

ROOT = Path(__file__).resolve().parents[2]
runner = CliRunner()


def _example_module():
    p = ROOT / "examples" / "signals" / "bench_ring_accelerometer.py"
    spec = importlib.util.spec_from_file_location("bench_ring_accelerometer", p)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def bench_signal(tmp_path_factory):
    return _example_module().make(tmp_path_factory.mktemp("sig") / "bench.nc")


@pytest.mark.parametrize("mode", ["speed", "tacho"])
def test_analyze_writes_report(bench_signal, tmp_path, mode):
    cfg = str(ROOT / "examples" / "hammami_back_to_back.toml")
    args = ["analyze", str(bench_signal), "--config", cfg, "--out", str(tmp_path)]
    args += ["--speed", "motor=1498.5"] if mode == "speed" else ["--reference", "motor"]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    for f in ("order_spectrum.png", "spectrogram.png", "tsa.png", "cepstrum.png",
              "indicators.csv", "markers.csv", "order_spectrum.nc"):
        assert (tmp_path / f).is_file(), f
    spec = xr.open_dataarray(tmp_path / "order_spectrum.nc")
    band = spec.sel(order=slice(10, 16))
    peak = float(band["order"][int(np.argmax(band.values))])
    # dominant planet-pass component 66 carrier orders = 66·16/81 motor orders (seed 003 §4.1)
    assert peak == pytest.approx(66 * 16 / 81, abs=0.02)
    ind = pd.read_csv(tmp_path / "indicators.csv")
    assert {"rms", "kurtosis", "crest_factor"} <= set(ind.columns)
    assert "FM4" in ind.columns  # gear indicators of the sun (on the motor shaft)


def test_analyze_bad_input_is_one_message(bench_signal, tmp_path):
    cfg = str(ROOT / "examples" / "hammami_back_to_back.toml")
    res = runner.invoke(app, ["analyze", str(bench_signal), "--config", cfg, "--speed",
                              "motor=-5", "--out", str(tmp_path)])
    assert res.exit_code == 2
    assert "speed must be > 0" in res.output
    res = runner.invoke(app, ["analyze", str(tmp_path / "missing.wav"), "--config", cfg,
                              "--speed", "motor=1000"])
    assert res.exit_code == 2 and "does not exist" in res.output


def test_signal_io_round_trips(tmp_path):
    from scipy.io import wavfile

    x = np.sin(np.linspace(0, 20, 1000))
    wavfile.write(tmp_path / "a.wav", 4000, (x * 20000).astype(np.int16))
    r = read_signal(tmp_path / "a.wav")
    assert r.fs == 4000 and np.max(np.abs(r.x - x * 20000 / 32768)) < 1e-4
    pd.DataFrame({"time": np.arange(1000) / 500.0, "acc": x}).to_csv(tmp_path / "a.csv",
                                                                     index=False)
    r = read_signal(tmp_path / "a.csv")
    assert r.fs == pytest.approx(500.0) and np.allclose(r.x, x)
    np.save(tmp_path / "a.npy", x)
    with pytest.raises(InputError, match="pass fs"):
        read_signal(tmp_path / "a.npy")
    assert read_signal(tmp_path / "a.npy", fs=100).fs == 100
    with pytest.raises(InputError, match="fs: sample rate must be > 0"):
        read_signal(tmp_path / "a.npy", fs=-1)
    np.savez(tmp_path / "a.npz", x=x, fs=250.0, pulse_times=np.arange(5) * 0.5)
    r = read_signal(tmp_path / "a.npz")
    assert r.fs == 250.0 and r.pulse_times.size == 5
    assert read_pulse_times(tmp_path / "a.npz").size == 5
    (tmp_path / "a.xyz").write_text("1\n2\n")
    with pytest.raises(InputError, match="unsupported"):
        read_signal(tmp_path / "a.xyz")


def test_pulse_times_from_netcdf_and_csv(tmp_path):
    from geardyn.signal_io import write_signal_netcdf

    tp = np.arange(1, 6) * 0.25
    write_signal_netcdf(tmp_path / "s.nc", np.zeros(64), 100.0, pulse_times=tp)
    np.testing.assert_allclose(read_pulse_times(tmp_path / "s.nc"), tp)
    assert read_signal(tmp_path / "s.nc").fs == 100.0
    pd.DataFrame({"t": tp}).to_csv(tmp_path / "p.csv", index=False)
    np.testing.assert_allclose(read_pulse_times(tmp_path / "p.csv"), tp)
    pd.DataFrame({"t": tp[::-1]}).to_csv(tmp_path / "bad.csv", index=False)
    with pytest.raises(InputError, match="strictly increasing"):
        read_pulse_times(tmp_path / "bad.csv")


def test_analyze_ias_from_encoder_edges(tmp_path):
    """Encoder edges of the motor shaft whose speed fluctuates at the mesh order 1040/81
    (seed 003 bench): the IAS order spectrum peaks there (non-integer order)."""
    from geardyn.sensors import pulse_times_from_angle

    w0, eps, k = 2 * np.pi * 1498.5 / 60, 0.002, 1040 / 81
    t = np.linspace(0, 81 / (1498.5 / 60), 400_001)  # 81 revs: order 1040/81 on a bin
    theta = w0 * t + eps / k * np.sin(k * w0 * t)
    edges = pulse_times_from_angle(t, theta, 1000)
    pd.DataFrame({"t": edges}).to_csv(tmp_path / "edges.csv", index=False)
    cfg = str(ROOT / "examples" / "hammami_back_to_back.toml")
    res = runner.invoke(app, ["analyze", str(tmp_path / "edges.csv"), "--config", cfg,
                              "--ias-ppr", "1000", "--clock", "80e6", "--reference", "motor",
                              "--out", str(tmp_path / "rep")])
    assert res.exit_code == 0, res.output
    spec = xr.open_dataarray(tmp_path / "rep" / "order_spectrum.nc")
    band = spec.sel(order=slice(2, 100))
    peak = float(band["order"][int(np.argmax(band.values))])
    revs = theta[-1] / (2 * np.pi)
    assert peak == pytest.approx(k, abs=1.0 / revs)
    assert float(band.max()) == pytest.approx(eps * w0, rel=0.02)


def test_analyze_runup_with_tacho_writes_order_speed_map(tmp_path):
    fs, f0, f1, dur = 20_000.0, 10.0, 50.0, 4.0
    t = np.arange(int(dur * fs)) / fs
    a = (f1 - f0) / dur
    theta = 2 * np.pi * (f0 * t + 0.5 * a * t**2)
    x = np.cos(3 * theta) + 0.5 * np.cos(1040 / 81 * theta)  # order 3 + bench mesh order
    k = np.arange(1, 120)
    tp = (-f0 + np.sqrt(f0**2 + 2 * a * k)) / a
    np.savez(tmp_path / "runup.npz", x=x, fs=fs, pulse_times=tp)
    cfg = str(ROOT / "examples" / "hammami_back_to_back.toml")
    res = runner.invoke(app, ["analyze", str(tmp_path / "runup.npz"), "--config", cfg,
                              "--reference", "motor", "--out", str(tmp_path / "rep")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "rep" / "order_speed_map.png").is_file()
    assert (tmp_path / "rep" / "waterfall.png").is_file()
    spec = xr.open_dataarray(tmp_path / "rep" / "order_spectrum.nc")
    for order, amp in ((3.0, 1.0), (1040 / 81, 0.5)):
        band = spec.sel(order=slice(order - 0.5, order + 0.5))
        i = int(np.argmax(band.values))
        assert float(band["order"][i]) == pytest.approx(order, abs=0.02)
        assert float(band[i]) == pytest.approx(amp, rel=0.16)  # ≤ Hann scalloping
