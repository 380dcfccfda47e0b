"""Figures a reader can use (issue 9, item 5): every axis labelled with a unit, dB colour bars,
one legend entry per family of marker lines, marker labels that do not overlap, range options
honoured, and result ``.plot()`` methods that return a figure without saving or switching the
backend."""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from typer.testing import CliRunner  # noqa: E402

import geardyn  # noqa: E402, F401 - registers ds.geardyn
from geardyn.cli import app  # noqa: E402
from geardyn.errors import InputError  # noqa: E402
from geardyn.gears.pe_stiffness import mesh_stiffness  # noqa: E402
from geardyn.gears.plot import plot_stiffness, stiffness_figure  # noqa: E402
from geardyn.kinematics.frequencies import characteristic_frequencies  # noqa: E402
from geardyn.models.planetary.build import model_from_config  # noqa: E402
from geardyn.models.planetary.modal import modes  # noqa: E402
from geardyn.plotting import plot_result  # noqa: E402
from geardyn.results import LAYOUT, shaft_variables  # noqa: E402
from geardyn.signal.annotate import KINDS, spectral_markers  # noqa: E402
from geardyn.signal.cepstrum import power_cepstrum  # noqa: E402
from geardyn.signal.plots import (  # noqa: E402
    FAMILY_NAMES,
    plot_cepstrum,
    plot_map,
    plot_spectrum,
    plot_tsa,
    plot_waterfall,
)
from geardyn.signal.spectra import angular_spectrogram, order_spectrum, stft  # noqa: E402

from .gears.seed002 import seed002_low  # noqa: E402

EX = Path(__file__).resolve().parents[1] / "examples"
UNIT = re.compile(r"(\[[^\]]+\]|\([^)]+\))")


@pytest.fixture(autouse=True)
def _close_and_stay(tmp_path, monkeypatch):
    """Each test runs in an empty directory (to see any file written) and closes its figures;
    the backend must not change."""
    monkeypatch.chdir(tmp_path)
    backend = matplotlib.get_backend()
    yield
    assert matplotlib.get_backend() == backend
    plt.close("all")


def assert_axes_labelled(fig: Figure) -> None:
    """Every axis has a non-empty label with a unit in brackets or parentheses (colour bars:
    their long axis)."""
    assert fig.axes
    for ax in fig.axes:
        if ax.get_label() == "<colorbar>":
            labels = [ax.get_ylabel() or ax.get_xlabel()]
        else:
            labels = [ax.get_xlabel(), ax.get_ylabel()]
        for lab in labels:
            assert lab.strip(), f"unlabelled axis in {ax.get_title()!r}"
            assert UNIT.search(lab), f"no unit in {lab!r}"


def colorbar_labels(fig: Figure) -> list[str]:
    return [ax.get_ylabel() for ax in fig.axes if ax.get_label() == "<colorbar>"]


def assert_no_file_written(tmp_path: Path) -> None:
    assert list(tmp_path.iterdir()) == []


# ---- signal figures --------------------------------------------------------------------


@pytest.fixture(scope="module")
def bench_markers():
    """Marker table of the seed 003 back-to-back bench at 1498.5 rpm of the motor."""
    cfg = geardyn.load_config(EX / "hammami_back_to_back.toml")
    kin = geardyn.analyze_kinematics(cfg)
    return spectral_markers(characteristic_frequencies(kin, {"motor": 1498.5}))


def _angle_signal(spr: int = 256, revs: int = 64) -> np.ndarray:
    th = np.arange(spr * revs) / spr
    rng = np.random.default_rng(0)
    return np.sin(2 * np.pi * 13.04 * th) + 0.1 * rng.normal(size=th.size)


def test_spectrum_legend_per_family_labels_and_ranges(bench_markers, tmp_path):
    spec = order_spectrum(_angle_signal(), 256)
    fig = plot_spectrum(spec, bench_markers, xmax=40.0, title="bench", ymax=2.0, units="m/s²")
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    assert ax.get_xlim() == (0.0, 40.0)
    assert ax.get_ylim()[1] == pytest.approx(2.0)
    assert "[m/s²]" in ax.get_ylabel() and "[events/rev]" in ax.get_xlabel()
    # one legend entry per family with a marker inside the range, not one per line
    inside = set(bench_markers.loc[bench_markers["order"].between(0, 40), "kind"])
    want = [FAMILY_NAMES[k] for k in KINDS if k in inside]
    assert len(want) >= 4  # shaft, mesh, sideband, planet-pass families at least
    assert [t.get_text() for t in ax.get_legend().get_texts()] == want
    assert len(ax.lines) > 2 * len(want)  # many marker lines, few legend entries
    # marker labels: inside the axes, no two overlap
    fig.draw_without_rendering()
    r = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(r) for t in ax.texts]
    assert len(boxes) >= 3
    frame = ax.get_window_extent(r)
    assert all(b.x0 >= frame.x0 - 0.5 and b.x1 <= frame.x1 + 0.5 for b in boxes)
    for a, b in itertools.combinations(boxes, 2):
        assert not a.overlaps(b)
    assert_axes_labelled(fig)
    assert_no_file_written(tmp_path)


def test_frequency_spectrum_legend_uses_hz(bench_markers):
    x = _angle_signal()
    from geardyn.signal.spectra import amplitude_spectrum

    spec = amplitude_spectrum(x, 8192.0)
    fig = plot_spectrum(spec, bench_markers, xmax=500.0, kinds=["mesh", "sideband"])
    ax = fig.axes[0]
    assert ax.get_xlabel() == "frequency [Hz]"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        FAMILY_NAMES["mesh"], FAMILY_NAMES["sideband"]]
    assert "[signal units]" in ax.get_ylabel()


def test_map_db_colour_bar_and_ranges(tmp_path):
    rng = np.random.default_rng(1)
    fs = 4096.0
    t = np.arange(int(4 * fs)) / fs
    m = stft(np.sin(2 * np.pi * 300 * t) + 0.01 * rng.normal(size=t.size), fs, nperseg=512)
    fig = plot_map(m, ymax=600.0, xmax=3.0, units="m/s²", title="spectrogram")
    ax = fig.axes[0]
    assert ax.get_ylim() == (0.0, 600.0)
    assert ax.get_xlim()[1] == 3.0
    assert ax.get_xlabel() == "time [s]" and ax.get_ylabel() == "frequency [Hz]"
    (cb,) = colorbar_labels(fig)
    assert "dB" in cb and "m/s²" in cb
    assert_axes_labelled(fig)
    # order map against speed, and its waterfall
    spr = 256
    x = _angle_signal(spr, 64)
    speed = np.linspace(1000, 1500, x.size)
    om = angular_spectrogram(x, spr, revs_per_segment=8, speed=speed)
    fig2 = plot_map(om, ymax=40.0)
    assert fig2.axes[0].get_xlabel() == "speed [rpm]"
    assert fig2.axes[0].get_ylabel() == "order [events/rev]"
    assert "dB" in colorbar_labels(fig2)[0]
    assert_axes_labelled(fig2)
    fig3 = plot_waterfall(om, ymax=30.0)
    assert fig3.axes[0].get_xlim() == (0.0, 30.0)
    assert_axes_labelled(fig3)
    assert_no_file_written(tmp_path)


def test_tsa_and_cepstrum_labels_and_ranges():
    x = _angle_signal()
    fig = plot_tsa(x[:256], "TSA", units="m/s²")
    assert fig.axes[0].get_xlim() == (0.0, 360.0)
    assert_axes_labelled(fig)
    fig = plot_cepstrum(power_cepstrum(x, 256.0), qmax=3.0, quefrency_units="rev")
    assert fig.axes[0].get_xlim() == (0.0, 3.0)
    assert fig.axes[0].get_xlabel() == "quefrency [rev]"
    assert_axes_labelled(fig)


def test_plot_on_given_axes_returns_its_figure():
    fig, (a1, a2) = plt.subplots(1, 2)
    spec = order_spectrum(_angle_signal(), 256)
    assert plot_spectrum(spec, ax=a1) is fig
    assert plot_tsa(np.ones(64), ax=a2) is fig
    assert len(fig.axes) == 2


# ---- result objects ----------------------------------------------------------------------


def test_stiffness_table_plot(tmp_path):
    table = mesh_stiffness(seed002_low(), n_per_cycle=32, n_cycles=2.0)
    fig = table.plot(pairs=True, xmax=1.5)
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    assert ax.get_xlim()[1] == 1.5
    assert ax.get_ylabel() == "mesh stiffness k [N/m]"
    assert "[mesh cycles]" in ax.get_xlabel()
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["total", "tooth pairs"]
    np.testing.assert_allclose(ax.lines[0].get_ydata(), table.total)
    assert_axes_labelled(fig)
    fig2 = stiffness_figure(table, table)
    assert_axes_labelled(fig2)
    assert_no_file_written(tmp_path)
    out = plot_stiffness(table, tmp_path / "k.png")  # the CLI's save helper
    assert out.is_file() and out.stat().st_size > 1000


@pytest.fixture(scope="module")
def lin_parker_modes():
    model = model_from_config(geardyn.load_config(EX / "planetary_lin_parker.toml"))
    return model, modes(model)


def test_modal_result_plot(lin_parker_modes, tmp_path):
    model, res = lin_parker_modes
    fig = res.plot()
    assert isinstance(fig, Figure)
    assert colorbar_labels(fig) == ["kinetic energy [% of the mode]",
                                    "strain energy [% of the mode]"]
    assert_axes_labelled(fig)
    max_hz = float(res.freq_hz[9]) + 1e-6
    fig = res.plot(kind="strain", max_hz=max_hz, model=model)
    ax = [a for a in fig.axes if a.get_label() != "<colorbar>"][0]
    assert len(ax.get_yticks()) == int(np.sum(res.freq_hz <= max_hz)) == 10
    assert_axes_labelled(fig)
    fig = res.plot(kind="frequencies", max_hz=max_hz)
    ax = fig.axes[0]
    assert max(max(ln.get_ydata()) for ln in ax.lines) <= max_hz
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert sorted(legend) == sorted(set(res.mode_type[:10]))
    assert ax.get_ylabel() == "natural frequency [Hz]"
    assert_axes_labelled(fig)
    with pytest.raises(InputError, match="kind: must be one of"):
        res.plot(kind="shapes")
    with pytest.raises(InputError, match="max_hz: no mode at or below"):
        res.plot(max_hz=-1.0)
    with pytest.raises(InputError, match="ax: this figure draws on 2 axes, got 1"):
        res.plot(ax=plt.subplots()[1])
    assert_no_file_written(tmp_path)


def test_cli_modes_plot_uses_modal_result_plot(tmp_path):
    out = tmp_path / "m.png"
    r = CliRunner().invoke(app, ["modes", str(EX / "planetary_lin_parker.toml"), "--max-hz",
                                 "3000", "--plot", str(out)])
    assert r.exit_code == 0, r.output
    assert out.is_file() and out.stat().st_size > 1000


# ---- simulation results (geardyn result layout) -----------------------------------------


@pytest.fixture(scope="module")
def result() -> xr.Dataset:
    """A small dataset in the result layout of docs/results.md: two shafts, two meshes, an
    accelerometer (time), an encoder IAS channel (angle, with its times) and a tacho."""
    t = np.linspace(0.0, 1.0, 501)
    w = np.stack([100.0 + 10 * t, -30.0 - 3 * t], axis=1)  # rad/s
    ang = np.cumsum(w, axis=0) * (t[1] - t[0])
    ds = xr.Dataset(shaft_variables(t, ["input", "output"], ang, w),
                    coords={"time": ("time", t, {"units": "s"}), "shaft": ["input", "output"],
                            "mesh": ["m1", "m2"]})
    ds["mesh_force"] = (("time", "mesh"), np.stack([1e3 + t, 2e3 - t], 1), {"units": "N"})
    ta = np.arange(0, 1.0, 1 / 2000)
    ds["sensors.acc"] = xr.DataArray(
        np.sin(2 * np.pi * 50 * ta), dims="sensors.acc.time",
        coords={"sensors.acc.time": ("sensors.acc.time", ta, {"units": "s"})},
        attrs={"units": "m/s²", "long_name": "housing acceleration", "sensor_kind":
               "accelerometer", "sampling": "time", "shaft": "input", "sample_rate_hz": 2000.0})
    th = np.arange(0, 2 * np.pi * 10, 2 * np.pi / 64)
    ds["sensors.ias"] = xr.DataArray(
        np.full(th.size, 100.0), dims="sensors.ias.angle",
        coords={"sensors.ias.angle": ("sensors.ias.angle", th, {"units": "rad",
                                                                 "long_name": "encoder angle"}),
                "sensors.ias.time": ("sensors.ias.angle", th / 100.0, {"units": "s"})},
        attrs={"units": "rad/s", "long_name": "instantaneous angular speed", "sampling": "angle",
               "sensor_kind": "encoder", "shaft": "input", "pulses_per_rev": 64})
    tp = np.arange(0.05, 1.0, 0.063)
    ds["sensors.tacho"] = xr.DataArray(
        tp, dims="sensors.tacho.pulse",
        attrs={"units": "s", "long_name": "tacho pulse time", "sampling": "events",
               "sensor_kind": "tacho", "shaft": "output"})
    ds.attrs.update({"geardyn_layout": LAYOUT, "model": "test", "status": "ok"})
    return ds


def test_plot_result_panels_and_units(result, tmp_path):
    fig = plot_result(result)
    assert isinstance(fig, Figure)
    assert len(fig.axes) == 5  # speeds, mesh forces, three channels
    speed, force, acc, ias, tacho = fig.axes
    assert speed.get_ylabel() == "shaft speed [rpm]" and speed.get_xlabel() == "time [s]"
    assert [t.get_text() for t in speed.get_legend().get_texts()] == ["input", "output"]
    assert force.get_ylabel() == "mesh_force [N]".replace("_", " ")
    assert acc.get_ylabel() == "housing acceleration [m/s²]"
    assert ias.get_xlabel() == "encoder angle [rad]"
    assert ias.get_ylabel() == "instantaneous angular speed [rad/s]"
    assert tacho.get_xlabel() == "tacho pulse time [s]"
    assert_axes_labelled(fig)
    assert_no_file_written(tmp_path)


def test_plot_result_selection_ranges_and_accessor(result):
    fig = result.geardyn.plot(shafts=["output"], meshes=[], channels=["acc"],
                              time_range=(0.2, 0.4))
    assert len(fig.axes) == 2
    assert fig.axes[0].get_xlim() == (0.2, 0.4) and fig.axes[1].get_xlim() == (0.2, 0.4)
    assert len(fig.axes[0].lines) == 1
    with pytest.raises(InputError, match=r"shafts: 'nope' not in the result \(shafts: input, "
                       r"output\)"):
        plot_result(result, shafts=["nope"])
    with pytest.raises(InputError, match="channels: 'x' not in the result"):
        plot_result(result, channels=["x"])
    with pytest.raises(InputError, match="nothing to plot"):
        plot_result(result, shafts=[], meshes=[], channels=[])
