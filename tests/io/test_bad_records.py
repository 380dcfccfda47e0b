"""Bad records end in a clear error or warning naming the file and the channel (issue 19):
wrong rate, too short, clipped, a tacho covering part of the record (and one longer than it,
trimmed), header-less / mixed-delimiter / ambiguous CSV, a channel that does not exist,
non-finite samples; and ``geardyn analyze`` on the CSVs of the issue's complaints."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from geardyn.errors import ConfigError, InputError
from geardyn.io import RecordWarning, read_raw, read_record
from geardyn.results import channel
from tests.conftest import EXAMPLES
from tests.io.conftest import analog_tacho, mapped_config

FS = 5000.0
RPM = 600.0  # 10 rev/s of the sun


def _write(tmp_path, x, tacho=None, name="r.csv", **kw):
    t = np.arange(x.size) / FS
    cols = {"time": t, "acc": x}
    if tacho is not None:
        cols["tacho"] = tacho
    pd.DataFrame(cols).to_csv(tmp_path / name, index=False, **kw)
    return tmp_path / name


def _signal(n=10_000):
    t = np.arange(n) / FS
    return np.sin(2 * np.pi * 123.0 * t) + 0.3 * np.sin(2 * np.pi * 471.0 * t)


def _cfg(tmp_path, extra="", speed=True):
    cfg = mapped_config(tmp_path, "acc", extra)
    if speed:
        cfg = cfg.model_copy(update={"measurement": cfg.measurement.model_copy(
            update={"speed_rpm": RPM})})
    return cfg


def test_wrong_rate_names_file_channel_and_both_rates(tmp_path):
    p = _write(tmp_path, _signal())
    with pytest.raises(InputError, match=r"r\.csv: channel 'ring_acc'.*4000 Hz.*own rate 5000"):
        read_record(p, cfg=_cfg(tmp_path, "sample_rate_hz = 4000"))


def test_no_rate_in_file_or_mapping(tmp_path):
    np.save(tmp_path / "r.npy", _signal())
    with pytest.raises(InputError, match=r"r\.npy: channel 'ring_acc'.*no sample rate.*"
                       "sample_rate_hz"):
        read_record(tmp_path / "r.npy", cfg=mapped_config(tmp_path, "0"))


def test_too_short_record(tmp_path):
    """0.15 s at 600 rpm is 1.5 revolutions of the sun; 2 are needed by default."""
    p = _write(tmp_path, _signal(750))
    cfg = _cfg(tmp_path)
    cfg = cfg.model_copy(update={"measurement": cfg.measurement.model_copy(
        update={"min_revolutions": 2.0})})
    with pytest.raises(InputError, match=r"r\.csv: the record covers 1\.5 revolutions of 'sun'"):
        read_record(p, cfg=cfg)


def test_clipped_stretch_is_a_warning_naming_the_channel(tmp_path):
    x = _signal()
    lim = 0.8 * np.max(x)
    p = _write(tmp_path, np.clip(x, -np.inf, lim))
    with pytest.warns(RecordWarning, match=r"r\.csv: channel 'ring_acc'.*clipped sample"):
        ds = read_record(p, cfg=_cfg(tmp_path))
    assert "clipped" in ds.attrs["warnings"]
    with warnings_none():
        read_record(_write(tmp_path, x, name="ok.csv"), cfg=_cfg(tmp_path))


class warnings_none:  # noqa: N801 - context manager: no RecordWarning inside
    def __enter__(self):
        import warnings

        self._c = warnings.catch_warnings()
        self._c.__enter__()
        warnings.simplefilter("error", RecordWarning)

    def __exit__(self, *a):
        return self._c.__exit__(*a)


TACHO = ('[[measurement.channels]]\nname = "sun_tacho"\nsource = "tacho"\nkind = "tacho"\n'
         'shaft = "sun"\npulses_per_rev = 4\n')


def test_tacho_covering_part_of_the_record_warns(tmp_path):
    x = _signal()
    t = np.arange(x.size) / FS
    tach = analog_tacho(t, 2 * np.pi * RPM / 60 * t, 4)
    tach[x.size // 2:] = 0.0  # the tacho drops out half-way
    p = _write(tmp_path, x, tach)
    with pytest.warns(RecordWarning, match=r"r\.csv: channel 'sun_tacho'.*covers 4\d% of it"):
        ds = read_record(p, cfg=_cfg(tmp_path, TACHO, speed=False))
    assert ds.time.values[-1] < 1.01  # the angle reference stops with the pulses


def test_tacho_longer_than_the_record_is_trimmed(tmp_path):
    """Pulse times [s] reaching 1 s before and after the signal: trimmed to one pulse beyond
    each end, no warning."""
    x = _signal()
    tp = np.arange(-1.0, x.size / FS + 1.0, 0.025)
    np.savez(tmp_path / "r.npz", acc=x, fs=FS, pulse_times=tp)
    extra = TACHO.replace('source = "tacho"', 'source = "pulse_times"') + \
        'signal = "pulse_times"\n'
    with warnings_none():
        ds = read_record(tmp_path / "r.npz", cfg=_cfg(tmp_path, 'file_units = "V"\n' + extra,
                                                      speed=False))
    p = channel(ds, "sun_tacho").values
    assert p[0] == pytest.approx(-0.025) and p[-1] == pytest.approx(2.0)
    assert ds.attrs["speed_rpm"] == pytest.approx(600.0)


def test_tacho_contradicting_the_stated_speed(tmp_path):
    x = _signal()
    t = np.arange(x.size) / FS
    p = _write(tmp_path, x, analog_tacho(t, 2 * np.pi * RPM / 60 * t, 4))
    cfg = _cfg(tmp_path, TACHO.replace("pulses_per_rev = 4", "pulses_per_rev = 1"), speed=False)
    cfg = cfg.model_copy(update={"measurement": cfg.measurement.model_copy(
        update={"speed_rpm": RPM})})
    with pytest.raises(InputError, match=r"channel 'sun_tacho'.*2400\.\d* rpm.*speed_rpm is 600"):
        read_record(p, cfg=cfg)


def test_missing_channel_lists_the_file_channels(tmp_path):
    p = _write(tmp_path, _signal())
    cfg = mapped_config(tmp_path, "accel")
    with pytest.raises(InputError, match=r"r\.csv: channel 'accel' does not exist; the file "
                       "has channels acc"):
        read_record(p, cfg=cfg)


def test_time_column_is_never_a_signal(tmp_path):
    p = _write(tmp_path, _signal())
    with pytest.raises(InputError, match="'time' is the time column; it is never analysed"):
        read_record(p, cfg=mapped_config(tmp_path, "time"))


def test_non_finite_sample(tmp_path):
    x = _signal()
    x[2500] = np.nan
    p = _write(tmp_path, x)
    with pytest.raises(InputError, match=r"channel 'ring_acc'.*1 non-finite.*t = 0\.5 s"):
        read_record(p, cfg=_cfg(tmp_path))


def test_mixed_delimiters_and_ambiguous_csv(tmp_path):
    (tmp_path / "mixed.csv").write_text("time,acc\n0,1.5\n0.001;2.5\n0.002,3.5\n")
    with pytest.raises(InputError, match=r"mixed\.csv: no consistent reading.*line 3"):
        read_raw(tmp_path / "mixed.csv")
    (tmp_path / "amb.csv").write_text("1,5\n3,5\n2,5\n4,5\n")
    with pytest.raises(InputError, match=r"amb\.csv: ambiguous table.*2 column.*1 column"):
        read_raw(tmp_path / "amb.csv")
    rec = read_raw(tmp_path / "amb.csv", delimiter=",")
    assert list(rec.channels) == ["0", "1"]
    rec = read_raw(tmp_path / "amb.csv", delimiter=";", decimal=",")
    np.testing.assert_allclose(rec.channels["0"].values, [1.5, 3.5, 2.5, 4.5])


def test_units_row_and_bracket_units(tmp_path):
    (tmp_path / "u.csv").write_text("time;acc\nms;V\n0;1,5\n0,2;2,5\n0,4;3,5\n0,6;1\n")
    rec = read_raw(tmp_path / "u.csv")
    ch = rec.channels["acc"]
    assert ch.units == "V" and ch.fs == pytest.approx(5000.0)


def test_bad_mapping_is_a_config_error(tmp_path):
    import tomllib

    from geardyn.config.loader import parse_config

    data = tomllib.loads((EXAMPLES / "seed004_diagnose_sun_crack.toml").read_text())
    with pytest.raises(ConfigError, match=r"measurement\.channels\[0\] 'a'\.location: "
                       "unknown location 'nowhere'"):
        parse_config({**data, "measurement": {"channels": [{"name": "a",
                                                            "location": "nowhere"}]}})
    with pytest.raises(ConfigError, match=r"measurement\.channels\[0\] 'a'\.sensitivity: "
                       "'100 mV/' is not a quantity"):
        parse_config({**data, "measurement": {"channels": [
            {"name": "a", "location": "ring", "sensitivity": "100 mV/"}]}})


# ---------------------------------------------------------------- analyze: the cases
runner = CliRunner()
CFG = str(EXAMPLES / "planetary_lin_parker.toml")


@pytest.fixture(scope="module")
def tone(tmp_path_factory):
    d = tmp_path_factory.mktemp("tone")
    t = np.arange(20_000) / FS
    return d, t, np.sin(2 * np.pi * 100.0 * t)


def _analyze(path, *extra):
    from geardyn.cli import app

    return runner.invoke(app, ["analyze", str(path), "--config", CFG, "--speed", "sun=600",
                               "--out", str(path.parent / f"out_{path.stem}"), *extra])


def test_analyze_headerless_csv_uses_the_signal_not_the_time(tone):
    d, t, x = tone
    pd.DataFrame({"t": t, "x": x}).to_csv(d / "nohead.csv", header=False, index=False)
    res = _analyze(d / "nohead.csv")
    assert res.exit_code == 0, res.output
    assert "20000 samples at 5000 Hz" in " ".join(res.output.split())


def test_analyze_several_columns_need_channel(tone):
    d, t, x = tone
    pd.DataFrame({"time": t, "a": x, "b": -x}).to_csv(d / "two.csv", sep=";", decimal=",",
                                                      index=False)
    res = _analyze(d / "two.csv")
    assert res.exit_code == 2
    assert "holds 2 signal channels; choose one with --channel" in " ".join(res.output.split())
    res = _analyze(d / "two.csv", "--channel", "b")
    assert res.exit_code == 0, res.output


def test_analyze_wav_sensitivity_and_headerless_tacho(tone):
    """WAV with --full-scale/--sensitivity; a header-less tacho CSV keeps its first pulse;
    a tacho longer than the signal is trimmed, not refused."""
    import soundfile as sf

    from geardyn.signal_io import read_pulse_times, read_signal

    d, t, x = tone
    sf.write(d / "a.wav", 0.5 * x, int(FS), subtype="PCM_16")
    r = read_signal(d / "a.wav", full_scale="10 V", sensitivity="100 mV/g")
    assert r.units == "m/s^2"
    assert np.max(np.abs(r.x - 0.5 * x * 10 / (0.1 / 9.80665))) < (0.5 + 0.5) * 10 / 2**15 \
        / (0.1 / 9.80665)
    tp = np.arange(-0.5, 5.0, 0.1)
    pd.DataFrame({"tp": tp}).to_csv(d / "tacho.csv", header=False, index=False)
    np.testing.assert_allclose(read_pulse_times(d / "tacho.csv"), tp)
    res = _analyze(d / "a.wav", "--tacho", str(d / "tacho.csv"), "--full-scale", "10 V",
                   "--sensitivity", "100 mV/g")
    assert res.exit_code == 0, res.output
    text = " ".join(res.output.split())
    # the tacho spans −0.5–4.9 s, the signal 0–4 s: trimmed, with the wrong-rate hint
    assert "pulses span -0.5–4.9 s, the signal 0–3.9998 s" in text and "check --fs" in text


def test_analyze_through_the_measurement_mapping(tmp_path, sim_run):
    """analyze with a [measurement] mapping: the mapped channel in m/s², the speed from the
    analog tacho channel; --speed is refused (the mapping gives the speed)."""
    from geardyn.cli import app

    _, ds = sim_run
    from tests.diagnosis.test_measured import MAPPING, export

    path = export(ds, tmp_path / "rec.csv")
    cfg = tmp_path / "m.toml"
    cfg.write_text((EXAMPLES / "seed004_diagnose_sun_crack.toml").read_text()
                   + MAPPING.format(name="ring_acc").replace("min_revolutions = 1.0",
                                                             "min_revolutions = 0.5"))
    res = runner.invoke(app, ["analyze", str(path), "--config", str(cfg), "--out",
                              str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    assert "channel 'ring_acc' of rec.csv" in " ".join(res.output.split())
    # part 5: the spectra reach the sensor's Nyquist frequency (5 kHz / 2, its 1.2 kHz housing
    # mode included), in the channel's units
    import xarray as xr

    spec = xr.load_dataarray(tmp_path / "out" / "order_spectrum.nc")
    assert spec.attrs["units"] == "m/s^2"
    f_ref = float(ds.speed_rpm.sel(shaft="sun").mean()) / 60.0
    assert float(spec["order"].max()) >= 0.9 * 2500.0 / f_ref
    assert (tmp_path / "out" / "order_spectrum_band.png").is_file()
    res = runner.invoke(app, ["analyze", str(path), "--config", str(cfg), "--speed", "sun=30",
                              "--out", str(tmp_path / "out2")])
    assert res.exit_code == 2 and "[measurement] section maps the record" in \
        " ".join(res.output.split())
