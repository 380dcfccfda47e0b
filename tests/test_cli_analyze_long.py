"""``geardyn analyze`` on long records: the bounded-memory path (cli.long_record) gives the
results of the whole-record path (peak memory is measured in benchmarks/bench_analyze_memory)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import geardyn.cli.analyze as analyze_cli
import geardyn.cli.long_record as long_record
from geardyn.cli import app
from geardyn.signal import resample_to_angle, signal_indicators

ROOT = Path(__file__).resolve().parents[1]
runner = CliRunner()


def test_chunked_indicators_equal_whole_record():
    rng = np.random.default_rng(1)
    x = (rng.standard_t(5, 100_003) + 0.3).astype(np.float32)  # heavy tails, offset
    whole = signal_indicators(np.asarray(x, float))
    chunked = long_record.chunked_indicators(x, chunk=997)
    for key, value in whole.items():
        assert chunked[key] == pytest.approx(value, rel=1e-9), key


def test_resample_chunked_joins_without_seams(monkeypatch):
    monkeypatch.setattr(long_record, "CHUNK", 1 << 14)
    monkeypatch.setattr(long_record, "MARGIN", 1 << 11)
    fs, f_rot, n = 20_000.0, 25.0, 150_000
    t = np.arange(n) / fs
    x = np.cos(2 * np.pi * 12.8 * f_rot * t) + 0.2 * np.cos(2 * np.pi * 3 * f_rot * t)
    whole = resample_to_angle(x, fs, 2 * np.pi * f_rot * t, samples_per_rev=128)
    parts = long_record.resample_chunked(x.astype(np.float32), fs,
                                         lambda tt: 2 * np.pi * f_rot * tt, 128)
    assert parts.x.size == whole.x.size
    assert parts.angle0 == pytest.approx(whole.angle0)
    assert parts.max_valid_order == pytest.approx(whole.max_valid_order)
    # float32 record, chunk-wise zero-phase filter: equal to 1e-5 of the amplitude
    assert np.max(np.abs(parts.x - whole.x)) < 1e-5
    assert np.allclose(parts.time, whole.time, atol=1e-12)


def test_long_path_end_to_end(tmp_path, monkeypatch):
    """The bounded-memory path of analyze (forced by a low LONG_SAMPLES) on a tacho record:
    order spectrum peaks at the orders and amplitudes of the synthetic signal (order 3,
    amplitude 1; planetary mesh order 1040/81 of the Hammami bench motor, amplitude 0.5) and
    raw indicators equal to the whole-record ones."""
    fs, f_rot, n = 10_000.0, 24.975, 100_000  # 1498.5 rpm, 10 s
    t = np.arange(n) / fs
    th = 2 * np.pi * f_rot * t
    x = (np.cos(3 * th) + 0.5 * np.cos(1040 / 81 * th)
         + 0.05 * np.random.default_rng(0).standard_normal(n)).astype(np.float32)
    np.save(tmp_path / "s.npy", x)
    np.save(tmp_path / "tacho.npy", np.arange(0.0, n / fs, 1 / f_rot))
    cfg = str(ROOT / "examples" / "hammami_back_to_back.toml")
    monkeypatch.setattr(analyze_cli, "LONG_SAMPLES", 50_000)
    monkeypatch.setattr(long_record, "CHUNK", 1 << 15)
    monkeypatch.setattr(long_record, "FEATURE_SAMPLES", 1 << 16)
    r = runner.invoke(app, ["analyze", str(tmp_path / "s.npy"), "--config", cfg, "--fs",
                            str(fs), "--tacho", str(tmp_path / "tacho.npy"), "--reference",
                            "motor", "--out", str(tmp_path / "long")])
    assert r.exit_code == 0, r.output
    assert "long record" in r.output
    spec = xr.open_dataarray(tmp_path / "long" / "order_spectrum.nc")
    for order, amp in ((3.0, 1.0), (1040 / 81, 0.5)):
        band = spec.sel(order=slice(order - 0.3, order + 0.3))
        assert float(band["order"][int(np.argmax(band.values))]) == pytest.approx(order,
                                                                                    abs=0.01)
        assert float(band.max()) == pytest.approx(amp, rel=0.16)  # ≤ Hann scalloping
    import pandas as pd

    raw = pd.read_csv(tmp_path / "long" / "indicators.csv").iloc[0]
    whole = signal_indicators(np.asarray(x, float))
    for key in ("rms", "peak", "kurtosis", "crest_factor"):
        assert raw[key] == pytest.approx(whole[key], rel=1e-6), key
    spectrogram = tmp_path / "long" / "spectrogram.png"
    assert spectrogram.is_file()
