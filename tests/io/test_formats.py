"""Round trip through each format's own writer (issue 19 "done when"): a simulated ring
accelerometer channel [m/s²] written as volts of a 100 mV/g transducer (or in m/s² where the
format carries units) by pandas, soundfile, numpy, scipy.io.savemat, h5py, npTDMS, pyuff,
asammdf and xarray is read back by :func:`geardyn.io.read_record` with the [measurement]
mapping: the same values (to the format's precision), the same sample rate, units m/s²."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from geardyn.io import read_raw, read_record
from geardyn.results import channel
from tests.io.conftest import SENS_V_PER_MS2, mapped_config


@pytest.fixture(scope="module")
def acc(sim_run):
    _, ds = sim_run
    ch = channel(ds, "ring_acc")
    return ch.time, ch.values, float(ch.sample_rate_hz)


def _check(tmp_path, path, source, acc, extra="", rtol=1e-12, atol=0.0):
    t, x, fs = acc
    ds = read_record(path, cfg=_cfg(tmp_path, source, extra))
    ch = channel(ds, "ring_acc")
    assert ch.units == "m/s^2"
    assert ch.sample_rate_hz == pytest.approx(fs, rel=1e-9)
    assert ch.values.size == x.size
    np.testing.assert_allclose(ch.values, x, rtol=rtol, atol=atol * np.max(np.abs(x)))
    assert ds.attrs["model"] == "measured" and ds.attrs["source_file"] == str(path)
    return ds


@pytest.mark.parametrize(("sep", "decimal", "header"), [
    (",", ".", True), (";", ",", True), ("\t", ".", True), (" ", ".", True), (",", ".", False),
    (";", ",", False)])
def test_csv_variants(tmp_path, acc, sep, decimal, header):
    """pandas to_csv with varied delimiter, decimal mark and header: delimiter, decimal and
    header are detected, the time column gives the rate and is not a channel."""
    t, x, fs = acc
    df = pd.DataFrame({"time [s]": t, "acc [V]": x * SENS_V_PER_MS2, "aux [V]": 0.5 * x})
    path = tmp_path / "rec.csv"
    df.to_csv(path, sep=sep, decimal=decimal, header=header, index=False)
    raw = read_raw(path)
    assert raw.time_channel == ("time" if header else "0")
    assert list(raw.channels) == (["acc", "aux"] if header else ["1", "2"])
    extra = "" if header else 'file_units = "V"'
    _check(tmp_path, path, "acc" if header else "1", acc, extra)


def test_wav_full_scale_and_sensitivity(tmp_path, acc):
    """soundfile PCM_24 and FLOAT: full_scale 20 V and 100 mV/g give m/s² to within the
    24-bit quantisation, half a step q = 20 V / 2^23 / sensitivity plus |v|·q for libsndfile's
    float → int scale of 2^23 − 1 read back as 1/2^23; float32 to its 2^-24 relative
    precision."""
    import soundfile as sf

    t, x, fs = acc
    v = x * SENS_V_PER_MS2 / 20.0
    assert np.max(np.abs(v)) < 1
    for subtype, tol in (("PCM_24", 20.0 / 2**23 / SENS_V_PER_MS2), ("FLOAT", None)):
        path = tmp_path / f"rec_{subtype}.wav"
        sf.write(path, np.column_stack([v, -v]), int(fs), subtype=subtype)
        ds = read_record(path, cfg=_cfg(tmp_path, "0", 'full_scale = "20 V"'))
        ch = channel(ds, "ring_acc")
        assert ch.units == "m/s^2" and ch.sample_rate_hz == fs
        err = np.max(np.abs(ch.values - x))
        bound = (0.5 + np.max(np.abs(v))) * tol if tol else 2**-23 * np.max(np.abs(x))
        assert err <= bound


def _cfg(tmp_path, source, extra=""):
    cfg = mapped_config(tmp_path, source, extra)
    return cfg.model_copy(update={"measurement": cfg.measurement.model_copy(
        update={"speed_rpm": 34.0})})


def test_numpy_npy_npz(tmp_path, acc):
    t, x, fs = acc
    np.save(tmp_path / "rec.npy", np.column_stack([x * SENS_V_PER_MS2, x]))
    _check(tmp_path, tmp_path / "rec.npy", "0", acc,
           f'file_units = "V"\nsample_rate_hz = {fs}')
    np.savez(tmp_path / "rec.npz", acc=x * SENS_V_PER_MS2, fs=fs)
    _check(tmp_path, tmp_path / "rec.npz", "acc", acc, 'file_units = "V"')


def test_mat_v5_and_v73(tmp_path, acc):
    """scipy.io.savemat (v5) with fs and a time vector; h5py with the MATLAB 7.3 header
    (column-major storage: an n × 1 column is an h5py (1, n) dataset)."""
    import h5py
    from scipy.io import savemat

    t, x, fs = acc
    savemat(tmp_path / "rec5.mat", {"acc": (x * SENS_V_PER_MS2)[:, None], "t": t[:, None]})
    _check(tmp_path, tmp_path / "rec5.mat", "acc", acc, 'file_units = "V"')
    p = tmp_path / "rec73.mat"
    with h5py.File(p, "w", userblock_size=512) as f:
        for name, a in (("acc", x * SENS_V_PER_MS2), ("fs", np.array([fs]))):
            d = f.create_dataset(name, data=a[None, :])
            d.attrs["MATLAB_class"] = np.bytes_("double")
    with open(p, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file, HDF5 schema 1.00 .".ljust(116) + bytes(8) + b"\x00\x02IM")
    _check(tmp_path, p, "acc", acc, 'file_units = "V"')


def test_tdms(tmp_path, acc):
    """npTDMS writer: wf_increment gives the rate, unit_string the units (V)."""
    from nptdms import ChannelObject, TdmsWriter

    t, x, fs = acc
    with TdmsWriter(tmp_path / "rec.tdms") as w:
        w.write_segment([ChannelObject("daq", "acc", x * SENS_V_PER_MS2, properties={
            "wf_increment": 1.0 / fs, "unit_string": "V", "wf_start_offset": 0.0})])
    _check(tmp_path, tmp_path / "rec.tdms", "daq/acc", acc)
    _check(tmp_path, tmp_path / "rec.tdms", "acc", acc)  # the channel name alone is unique


@pytest.mark.parametrize("binary", [0, 1])
def test_uff58(tmp_path, acc, binary):
    """pyuff dataset 58 (ASCII, E20.12: 1e-11 relative) and 58b (binary doubles), in m/s²."""
    import pyuff

    t, x, fs = acc
    d = pyuff.prepare_58(binary=binary, func_type=1, rsp_node=1, rsp_dir=3, ref_node=1,
                         ref_dir=1, id1="acc", rsp_ent_name="ring", ref_ent_name="ring",
                         ordinate_axis_units_lab="m/s^2", abscissa_axis_units_lab="s",
                         data=x, x=t, abscissa_spacing=1, ordinate_spec_data_type=12,
                         abscissa_spec_data_type=17, orddenom_spec_data_type=13)
    # mode "add" on a new file: pyuff 2.5's "overwrite" loses a binary set
    pyuff.UFF(str(tmp_path / "rec.uff")).write_sets([d], mode="add")
    cfg = mapped_config(tmp_path, "acc")
    spec = cfg.measurement.model_copy(update={"speed_rpm": 34.0, "channels": [
        cfg.measurement.channels[0].model_copy(update={"sensitivity": None})]})
    ds = read_record(tmp_path / "rec.uff", spec, cfg)
    ch = channel(ds, "ring_acc")
    assert ch.units == "m/s^2" and ch.sample_rate_hz == pytest.approx(fs, rel=1e-9)
    np.testing.assert_allclose(ch.values, x, rtol=1e-11, atol=1e-11 * np.max(np.abs(x)))


def test_mdf4(tmp_path, acc):
    from asammdf import MDF, Signal

    t, x, fs = acc
    with MDF(version="4.10") as m:
        m.append([Signal(x * SENS_V_PER_MS2, t, name="acc", unit="V")])
        m.save(tmp_path / "rec.mf4", overwrite=True)
    _check(tmp_path, tmp_path / "rec.mf4", "acc", acc)


def test_hdf5_any_layout_and_netcdf(tmp_path, acc):
    """HDF5 written by h5py with a group layout and the rate and units as attributes of the
    group and dataset; NetCDF by xarray with a time coordinate."""
    import h5py
    import xarray as xr

    t, x, fs = acc
    with h5py.File(tmp_path / "rec.h5", "w") as f:
        g = f.create_group("daq/run1")
        g.attrs["sample_rate"] = fs
        d = g.create_dataset("acc", data=x * SENS_V_PER_MS2)
        d.attrs["units"] = "V"
        g.create_dataset("other", data=np.zeros(7))
    _check(tmp_path, tmp_path / "rec.h5", "daq/run1/acc", acc)
    _check(tmp_path, tmp_path / "rec.h5", "acc", acc)  # the dataset name alone is unique
    xr.Dataset({"acc": ("time", x * SENS_V_PER_MS2, {"units": "V"})},
               coords={"time": t}).to_netcdf(tmp_path / "rec.nc")
    _check(tmp_path, tmp_path / "rec.nc", "acc", acc)
