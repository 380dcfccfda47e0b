"""The diagnosis report: one self-contained HTML page (``report.html``).

Sections: detection and localisation (when the verdict carries them); verdict (table, margin
chart, notes); machine, record, baseline and configured faults; kinematic tables (shaft
speeds, meshes, wheel fault orders, bearing orders, planet pass); order spectrum over the
sensor's whole band (up to the channel's Nyquist frequency in orders of the reference at the
record's mean speed, log-log, transfer-path modes marked) and annotated around the meshes
(healthy baseline against the record); envelope spectrum with the bearing and fault lines (and
the kurtogram of the band choice); TSA per component; spectrogram of the channel up to its
Nyquist frequency (log frequency axis, modes marked) and CWT of the TSA of the worst
component; indicator table with thresholds (alarm cells highlighted); what each indicator
shown means (:mod:`geardyn.diagnosis.explain`). Figures are embedded as PNG data URIs; the page
has no external file, stylesheet or script.

The worst indicator of a component is :attr:`ComponentVerdict.worst
<geardyn.diagnosis.verdict.ComponentVerdict.worst>` in the table and in the margin chart alike.

The features objects are those of :func:`geardyn.diagnosis.features.features_from_result`
(``table``, ``tsa``, ``order_spectrum``, ``envelope_spectrum``, ``band``, ``kurtogram``,
``markers``); missing artefacts (None) leave their figure out with a note.
"""

from __future__ import annotations

import base64
import html
import io
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr

from geardyn.checkpoint import write_text
from geardyn.diagnosis.explain import explain
from geardyn.diagnosis.verdict import Verdict, is_isolation_measure
from geardyn.errors import InputError

if TYPE_CHECKING:
    from geardyn.diagnosis.features import Features
    from geardyn.kinematics import CharacteristicFrequencies

_CSS = """
body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1100px;color:#222}
h1{font-size:1.5em}h2{border-bottom:1px solid #ccc;padding-top:.6em}
table{border-collapse:collapse;margin:.5em 0 1em;font-size:.85em}
th,td{border:1px solid #ccc;padding:2px 6px;text-align:right}
th{background:#f0f0f0}td.txt,th.txt{text-align:left}
td.alarm{background:#f8c4c4;font-weight:bold}td.healthy{background:#d4f0d4}
td.unknown{background:#eee;color:#666}td.uncertain{background:#fde2a6;font-weight:bold}
p.detected{background:#f8c4c4;padding:4px 8px}p.clear{background:#d4f0d4;padding:4px 8px}
p.uncertain{background:#fde2a6;padding:4px 8px}td.def{text-align:left;max-width:40em}
img{max-width:100%;display:block;margin:.3em 0 1em}
p.note{color:#666;font-size:.9em}
"""

#: Kinematic tables: (attribute, title, {column: header with unit}).
KINEMATIC_TABLES: tuple[tuple[str, str, dict[str, str]], ...] = (
    ("links", "Shafts", {"link": "link", "signed_rpm": "speed [rpm]", "hz": "rotation [Hz]",
                         "order": "order [events/rev]"}),
    ("meshes", "Meshes", {"pair": "pair", "carrier": "carrier", "teeth_a": "teeth a",
                          "teeth_b": "teeth b", "mesh_hz": "mesh [Hz]",
                          "mesh_order": "mesh order [events/rev]",
                          "hunting_period_s": "hunting period [s]"}),
    ("wheels", "Wheels (tooth-fault frequency)", {
        "wheel": "wheel", "link": "link", "teeth": "teeth", "meshes_with": "meshes with",
        "fault_hz": "fault [Hz]", "fault_order": "fault order [events/rev]"}),
    ("bearings", "Bearings", {"bearing": "bearing", "inner": "inner", "outer": "outer",
                              "ftf_hz": "FTF [Hz]", "bpfo_hz": "BPFO [Hz]", "bpfi_hz": "BPFI [Hz]",
                              "bsf_hz": "BSF [Hz]", "bpfo_order": "BPFO order [events/rev]",
                              "bpfi_order": "BPFI order [events/rev]"}),
    ("planet_pass", "Planet pass", {"set": "set", "n_planets": "planets",
                                    "planet_pass_hz": "planet pass [Hz]",
                                    "planet_pass_order": "planet pass order [events/rev]"}),
)

#: Indicator table columns: (verdict.indicator_table column, header with unit); ``unit`` is the
#: indicator's unit (:func:`geardyn.diagnosis.explain.explain`), that of value, mean, std and
#: threshold.
INDICATOR_COLUMNS = (
    ("component", "component"), ("kind", "kind"), ("indicator", "indicator"),
    ("unit", "unit"), ("value", "record value [unit]"), ("mean", "baseline mean [unit]"),
    ("std", "baseline std [unit]"), ("threshold", "threshold [unit]"),
    ("margin", "margin value/threshold [-]"),
)

#: Fill colour of a component state in the margin chart (CSS classes of the same names).
STATE_COLOURS = {"alarm": "tab:red", "uncertain": "tab:orange", "healthy": "tab:green",
                 "unknown": "0.7"}


# ---------------------------------------------------------------- HTML building blocks
def _fmt(v: Any) -> str:
    """A value as the report prints it: numbers to 4 significant digits, "–" for a missing or
    non-finite one (never "None"), mappings as "key value, …", lists comma-separated."""
    if v is None:
        return "–"
    if isinstance(v, bool | np.bool_):
        return "yes" if v else "no"
    if isinstance(v, float | np.floating):
        return "–" if not math.isfinite(float(v)) else f"{float(v):.4g}"
    if isinstance(v, dict):
        return ", ".join(f"{k} {_fmt(x)}" for k, x in v.items()) or "–"
    if isinstance(v, list | tuple):
        return ", ".join(_fmt(x) for x in v) or "–"
    return str(v)


#: Unit suffix of a run-setting name → label unit (machine section of the report).
_SETTING_UNITS = {"_s": "s", "_rpm": "rpm", "_hz": "Hz", "_m": "m"}


def _setting(prefix: str, key: str, value: Any) -> tuple[str, str] | None:
    """``("baseline t_end [s]", "1.2")`` for one baseline/record setting; None for a setting
    left at the config's value (``None``), the ensemble members summarised by their count."""
    if value is None:
        return None
    if key == "members" and isinstance(value, list):
        return (f"{prefix} ensemble members", f"{len(value)} (the drawn speeds, loads, errors "
                "and sensor variants of each are listed in verdict.json)")
    for suffix, unit in _SETTING_UNITS.items():
        if key.endswith(suffix):
            return f"{prefix} {key.removesuffix(suffix)} [{unit}]", _fmt(value)
    return f"{prefix} {key}", _fmt(value)


def html_table(
    df: pd.DataFrame,
    headers: dict[str, str] | None = None,
    cell_class: Callable[[int, str], str] | None = None,
) -> str:
    """An HTML table of ``df`` (columns renamed by ``headers``, which also selects and orders
    them); ``cell_class(row_index, column)`` gives an optional CSS class per cell."""
    headers = headers or {c: c for c in df.columns}
    cols = [c for c in headers if c in df.columns]
    head = "".join(
        f'<th class="txt">{html.escape(headers[c])}</th>' if df[c].dtype == object
        else f"<th>{html.escape(headers[c])}</th>" for c in cols
    )
    body = []
    for i, (_, r) in enumerate(df.iterrows()):
        cells = []
        for c in cols:
            cls = [cell_class(i, c)] if cell_class else []
            if df[c].dtype == object:
                cls.append("txt")
            attr = f' class="{" ".join(x for x in cls if x)}"' if any(cls) else ""
            cells.append(f"<td{attr}>{html.escape(_fmt(r[c]))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def figure_uri(fig: Any, dpi: int = 90) -> str:
    """A matplotlib figure as a ``data:image/png;base64,…`` URI (the figure is closed)."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def _img(fig: Any, alt: str) -> str:
    return f'<img src="{figure_uri(fig)}" alt="{html.escape(alt)}">'


def _note(text: str) -> str:
    return f'<p class="note">{html.escape(text)}</p>'


def _units(da: xr.DataArray | None, default: str = "") -> str:
    u = str(da.attrs.get("units", "")) if da is not None else ""
    return u or default


# ---------------------------------------------------------------- figures
def _axes(figsize: tuple[float, float]) -> tuple[Any, Any]:
    """A figure (not registered with pyplot, no backend switch) and its axes."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot()


def _mesh_xmax(freqs: CharacteristicFrequencies | None, spec: xr.DataArray) -> float:
    """Upper order of the zoom on the meshes: 3.3 × the highest mesh order (three harmonics
    and their sidebands), at most the spectrum's top."""
    top = float(spec[spec.dims[0]].values[-1])
    if freqs is None or freqs.meshes.empty:
        return top
    return min(top, 3.3 * float(freqs.meshes["mesh_order"].max()))


@dataclass(frozen=True)
class SensorBand:
    """Order range where a channel's content is: ``order_max`` (drawn up to), the channel's
    Nyquist order ``nyquist_order`` = (f_s/2)/f_ref (NaN if the channel is not sampled in time),
    the top of the analysed spectrum ``analysed_order``, the reference rotation frequency
    ``reference_hz`` [Hz] and the transfer-path mode frequencies ``modes_hz`` [Hz]."""

    order_max: float
    nyquist_order: float
    analysed_order: float
    reference_hz: float
    modes_hz: tuple[float, ...] = ()

    @property
    def modes_order(self) -> tuple[float, ...]:
        """Mode frequencies in orders of the reference (f_mode / f_ref)."""
        return tuple(f / self.reference_hz for f in self.modes_hz)

    @property
    def truncated(self) -> bool:
        """True when the analysed spectrum stops below the channel's Nyquist order."""
        return math.isfinite(self.nyquist_order) and self.analysed_order < self.nyquist_order


def sensor_band(analysed_order: float, reference_hz: float, sample_rate_hz: float | None = None,
                modes_hz: Iterable[float] = ()) -> SensorBand:
    """The order range to draw a channel's spectra over: up to its Nyquist frequency
    ``sample_rate_hz``/2 expressed in orders of the reference turning at ``reference_hz``
    (order = f / f_ref), at most ``analysed_order`` (the top of the computed spectrum); the
    whole analysed range when the sample rate is not known. ``modes_hz``: transfer-path mode
    frequencies (non-positive entries, the "no path" placeholder, are dropped).

    Example: Wang 2010 ring accelerometer, 5 kHz sampling, sun reference at 32.43 rpm
    (0.5404 Hz): Nyquist order 2500/0.5404 = 4626; its 1.2 kHz housing mode at order 2221."""
    f_ref = float(reference_hz)
    if not math.isfinite(f_ref) or f_ref <= 0:
        raise InputError(f"reference_hz: the reference rotation frequency must be a finite "
                         f"number > 0 [Hz], got {reference_hz!r}")
    top = float(analysed_order)
    if not math.isfinite(top) or top <= 0:
        raise InputError(f"analysed_order: the top of the spectrum must be a finite number > 0 "
                         f"[orders], got {analysed_order!r}")
    nyq = math.nan
    if sample_rate_hz is not None:
        fs = float(sample_rate_hz)
        if not math.isfinite(fs) or fs <= 0:
            raise InputError(f"sample_rate_hz: must be a finite number > 0 [Hz], got "
                             f"{sample_rate_hz!r}")
        nyq = 0.5 * fs / f_ref
    modes = []
    for f in modes_hz:
        f = float(f)
        if not math.isfinite(f):
            raise InputError(f"modes_hz: mode frequencies must be finite [Hz], got {f!r}")
        if f > 0:
            modes.append(f)
    return SensorBand(order_max=min(top, nyq) if math.isfinite(nyq) else top,
                      nyquist_order=nyq, analysed_order=top, reference_hz=f_ref,
                      modes_hz=tuple(modes))


def channel_sampling(ds: xr.Dataset | None, channel: str | None
                     ) -> tuple[float | None, tuple[float, ...]]:
    """``(sample rate [Hz] or None, transfer-path mode frequencies [Hz])`` of a result's
    channel: the rate of a time-sampled channel (``sample_rate_hz`` attribute, else from its
    sample times), None for an angle- or event-sampled one or when there is no channel; the
    modes from the ``transfer_modes_hz`` attribute (docs/results.md)."""
    if ds is None or not channel:
        return None, ()
    from geardyn.results import channel as get_channel

    ch = get_channel(ds, channel)
    raw = ch.attrs.get("transfer_modes_hz", ())
    modes = tuple(float(f) for f in np.atleast_1d(np.asarray(raw, float)) if f > 0)
    if ch.sampling != "time":
        return None, modes
    fs = ch.sample_rate_hz
    if not fs and ch.time.size >= 2:
        fs = 1.0 / float(np.median(np.diff(ch.time)))
    return (float(fs) if fs else None), modes


def _reference_hz(record: Features, freqs: CharacteristicFrequencies | None) -> float | None:
    """Reference rotation frequency [Hz] at the record's mean speed (else the kinematics')."""
    rpm = abs(float(getattr(record, "mean_rpm", math.nan)))
    if math.isfinite(rpm) and rpm > 0:
        return rpm / 60.0
    if freqs is not None and math.isfinite(freqs.reference_hz) and freqs.reference_hz > 0:
        return float(freqs.reference_hz)
    return None


def sensor_band_figure(record: xr.DataArray, healthy: xr.DataArray | None,
                       band: SensorBand, markers: pd.DataFrame | None, reference: str) -> Any:
    """Order spectrum over the sensor's band, log-log: record and healthy baseline, the mesh
    harmonics (dashed) and the transfer-path modes (dotted, labelled), a frequency axis [Hz]
    on top (f = order × f_ref)."""
    from geardyn.signal.plots import curve_points

    dim = record.dims[0]
    o = np.asarray(record[dim].values, float)
    y = np.asarray(record.values, float)
    keep = (o > 0) & (o <= band.order_max)
    fig, ax = _axes((10, 4))
    ax.plot(*curve_points(o[keep], y[keep], log_x=True), lw=0.5, color="0.2", label="record")
    if healthy is not None:
        ho = np.asarray(healthy[healthy.dims[0]].values, float)
        hk = (ho > 0) & (ho <= band.order_max)
        ax.plot(*curve_points(ho[hk], np.asarray(healthy.values, float)[hk], log_x=True),
                lw=0.5, color="tab:cyan", alpha=0.8, label="healthy baseline", zorder=1)
    ax.set_xscale("log")
    ax.set_yscale("log")
    lo = float(o[keep][0]) if keep.any() else 1.0
    ax.set_xlim(lo, band.order_max)
    pos = y[keep][y[keep] > 0]
    if pos.size:
        ax.set_ylim(max(pos.min(), pos.max() * 1e-7), pos.max() * 3)
    if markers is not None and len(markers):
        mesh = markers[(markers["kind"] == "mesh") & markers["order"].between(lo, band.order_max)]
        for i, r in enumerate(mesh.itertuples()):
            ax.axvline(r.order, color="tab:blue", lw=0.6, ls="--", alpha=0.6,
                       label="mesh harmonics" if i == 0 else None)
    for i, (f, om) in enumerate(zip(band.modes_hz, band.modes_order, strict=True)):
        if om <= band.order_max:
            ax.axvline(om, color="tab:red", lw=1.0, ls=":",
                       label="transfer-path mode" if i == 0 else None)
            ax.annotate(f"mode {f:.4g} Hz", (om, 0.97), xycoords=("data", "axes fraction"),
                        va="top", ha="right", fontsize=7, color="tab:red",
                        bbox={"fc": "w", "ec": "none", "alpha": 0.8, "pad": 1})
    ref = reference or "reference"
    ax.set_xlabel(f"order of {ref} [events/rev]")
    ax.set_ylabel(f"amplitude [{_units(record, 'channel units')}]")
    f_ref = band.reference_hz
    top = ax.secondary_xaxis("top", functions=(lambda x: x * f_ref, lambda f: f / f_ref))
    top.set_xlabel(f"frequency at the mean speed ({f_ref:.4g} Hz of {ref}) [Hz]")
    nyq = ("" if not math.isfinite(band.nyquist_order)
           else f"; channel Nyquist at order {band.nyquist_order:.4g}")
    ax.set_title(f"Order spectrum over the sensor band (record){nyq}", fontsize=9)
    ax.legend(loc="lower left", fontsize=7)
    return fig


def order_spectrum_figure(
    record: xr.DataArray,
    healthy: xr.DataArray | None,
    markers: pd.DataFrame | None,
    xmax: float,
    title: str,
) -> Any:
    """Record order spectrum (annotated) with the healthy baseline's behind it."""
    from geardyn.signal.plots import curve_points, plot_spectrum

    fig = plot_spectrum(record, markers, xmax, title)
    ax = fig.axes[0]
    ax.lines[0].set_label("record")
    if healthy is not None:
        dim = healthy.dims[0]
        ax.plot(*curve_points(healthy[dim].values, healthy.values, None, xmax), lw=0.6,
                color="tab:cyan", alpha=0.8, label="healthy baseline", zorder=1)
    ax.set_ylabel(f"amplitude [{_units(record, 'channel units')}]")
    _curve_legend(ax)
    return fig


def _curve_legend(ax: Any) -> None:
    """Legend of the record/healthy curves, keeping a legend already drawn (marker families)."""
    from matplotlib.legend import Legend

    curves = [ln for ln in ax.lines if not ln.get_label().startswith("_")]
    ax.add_artist(Legend(ax, curves, [ln.get_label() for ln in curves], loc="upper right",
                         fontsize=7))


def tsa_figure(component: str, record: xr.DataArray, healthy: xr.DataArray | None) -> Any:
    """One revolution of a component's TSA (record and healthy baseline) against its angle."""
    from geardyn.signal.plots import plot_tsa

    fig = plot_tsa(np.asarray(record.values, float), f"TSA of {component}")
    ax = fig.axes[0]
    ax.lines[0].set(label="record", color="0.2")
    if healthy is not None:
        ax.plot(_angle_deg(healthy), healthy.values, lw=0.8, color="tab:cyan", alpha=0.8,
                label="healthy baseline", zorder=1)
    ax.set_xlabel(f"angle of {component} [deg]")
    ax.set_ylabel(f"TSA [{_units(record, 'channel units')}]")
    ax.set_xlim(0, 360)
    _curve_legend(ax)
    fig.set_size_inches(10, 3)
    return fig


def _angle_deg(da: xr.DataArray) -> np.ndarray:
    return np.arange(da.size) * 360.0 / da.size


def cwt_figure(component: str, tsa_da: xr.DataArray, max_order: float) -> Any:
    """|CWT| (Morlet) of one revolution of a TSA: angle [deg] × order [events/rev] up to
    ``max_order`` (Wang 2010, ch. 9 localises a tooth fault this way). The TSA is periodic: it
    is first resampled (Fourier) to 8 samples per period of ``max_order`` and wrapped, so that
    the transform costs little and has no edge effect."""
    import pywt
    from scipy.signal import resample

    from geardyn.signal import cwt_morlet

    x = np.asarray(tsa_da.values, float)
    n = int(min(x.size, max(256, 2 ** math.ceil(math.log2(8 * max_order)))))
    if n < x.size:
        x = resample(x, n)
    centre = pywt.central_frequency("morl")
    hi = min(max_order, n / 2.5)
    orders = np.geomspace(max(1.0, hi / 60.0), hi, 64)
    cwt = cwt_morlet(np.tile(x, 3), fs=float(n), scales=centre * n / orders)
    mag = cwt.values[:, n:2 * n]
    fig, ax = _axes((10, 3.5))
    mesh = ax.pcolormesh(np.arange(n) * 360.0 / n, cwt["frequency"].values, mag,
                         shading="auto", cmap="viridis")
    fig.colorbar(mesh, ax=ax, label=f"|CWT| [{_units(tsa_da, 'channel units')}]")
    ax.set_yscale("log")
    ax.set_xlabel(f"angle of {component} [deg]")
    ax.set_ylabel("order [events/rev]")
    ax.set_title(f"Morlet CWT of the TSA of {component} (record)")
    return fig


def spectrogram_segment(sample_rate_hz: float, n_samples: int, resolve_hz: float | None) -> int:
    """STFT segment length: the power of two whose bin width f_s/n is at most ``resolve_hz``
    (None: f_s/64), with at least 4 segments in the record and at least 16 samples."""
    fs = float(sample_rate_hz)
    want = fs / resolve_hz if resolve_hz and resolve_hz > 0 else 64.0
    nper = int(2 ** math.ceil(math.log2(max(16.0, want))))
    return max(16, min(nper, int(2 ** math.floor(math.log2(max(16, n_samples // 4))))))


#: Records longer than this (samples) get a block-averaged spectrogram (at most 512 columns,
#: :func:`geardyn.cli.long_record.block_spectrogram`) instead of every STFT frame (a 3e7-sample
#: record would need ≈ 1 GB for its frames and draw millions of cells).
LONG_SAMPLES = 1 << 22


def spectrogram_figure(ds: xr.Dataset, channel: str, fmax: float | None = None,
                       resolve_hz: float | None = None, modes_hz: Sequence[float] = ()
                       ) -> Any | None:
    """STFT (time-sampled channel) or angular spectrogram (angle-sampled channel) in dB.

    Time-sampled: up to ``fmax`` [Hz] (default the channel's Nyquist frequency f_s/2) on a log
    frequency axis, so that the mesh lines and the structural resonances both show; segments
    resolve ``resolve_hz`` (:func:`spectrogram_segment`; the report passes half the lowest
    mesh frequency); the transfer-path modes ``modes_hz`` dotted."""
    from geardyn.results import channel as get_channel
    from geardyn.signal import angular_spectrogram, stft
    from geardyn.signal.plots import plot_map

    ch = get_channel(ds, channel)
    if ch.sampling == "time" and ch.values.size >= 64:
        fs = ch.sample_rate_hz or 1.0 / float(np.median(np.diff(ch.time)))
        nper = spectrogram_segment(fs, ch.values.size, resolve_hz)
        how = ""
        if ch.values.size > LONG_SAMPLES:  # a long record: mean STFT magnitude per block
            from geardyn.cli.long_record import block_spectrogram

            m = block_spectrogram(ch.values, fs, nperseg=nper)
            how = f", mean over blocks of {m.attrs['note'].split()[-2]} samples"
        else:
            m = stft(ch.values - ch.values.mean(), fs, nperseg=nper)
        m.attrs["units"] = ch.units
        top = min(fs / 2, fmax) if fmax else fs / 2
        fig = plot_map(m, ymax=top, title=f"Spectrogram of {channel} (segments of {nper} "
                       f"samples, {fs / nper:.3g} Hz bins{how})")
        ax = fig.axes[0]
        ax.set_yscale("log")
        ax.set_ylim(fs / nper, top)
        ax.set_ylabel("frequency [Hz]")
        ax.set_xlabel("time [s]")
        for i, f in enumerate(f for f in modes_hz if 0 < f <= top):
            ax.axhline(f, color="w", lw=1.0, ls=":",
                       label="transfer-path mode" if i == 0 else None)
            ax.annotate(f"mode {f:.4g} Hz", (0.01, f), xycoords=("axes fraction", "data"),
                        va="bottom", fontsize=7, color="w")
    elif ch.sampling == "angle" and ch.pulses_per_rev and ch.values.size >= 4 * ch.pulses_per_rev:
        revs = ch.values.size / ch.pulses_per_rev
        m = angular_spectrogram(ch.values - ch.values.mean(), ch.pulses_per_rev,
                                revs_per_segment=max(1.0, min(8.0, revs / 8)))
        m.attrs["units"] = ch.units
        fig = plot_map(m, title=f"Angular spectrogram of {channel} (orders of {ch.shaft})")
        fig.axes[0].set_ylabel(f"order of {ch.shaft} [events/rev]")
        fig.axes[0].set_xlabel(f"angle of {ch.shaft} [rev]")
    else:
        return None
    ax = fig.axes[0]
    if len(fig.axes) == 1:  # no colour bar drawn by plot_map
        fig.colorbar(ax.collections[0], ax=ax, label=f"amplitude [dB re 1 {ch.units or 'unit'}]")
    return fig


@dataclass(frozen=True)
class MarginRow:
    """One component of the margin chart: its state, its worst detection indicator and margin
    (:attr:`ComponentVerdict.worst <geardyn.diagnosis.verdict.ComponentVerdict.worst>`, the
    one the verdict table shows), every detection margin and every isolation-evidence
    margin."""

    component: str
    state: str
    worst: str
    worst_margin: float
    detection: tuple[float, ...]
    evidence: tuple[float, ...]


def margin_rows(verdict: Verdict) -> list[MarginRow]:
    """Rows of :func:`margin_figure`, one per component in verdict order (finite margins
    > 0 only: the chart is logarithmic)."""
    rows = []
    for name, c in verdict.components.items():
        w = c.worst
        det = tuple(float(v.margin) for k, v in c.indicators.items()
                    if not is_isolation_measure(k) and math.isfinite(v.margin) and v.margin > 0)
        ev = tuple(float(v.margin) for k, v in c.indicators.items()
                   if is_isolation_measure(k) and math.isfinite(v.margin) and v.margin > 0)
        rows.append(MarginRow(name, c.state, w[0] if w else "", float(w[1]) if w else math.nan,
                              det, ev))
    return rows


def margin_figure(verdict: Verdict) -> Any | None:
    """Horizontal bars: the worst detection indicator of each component (bar, coloured by the
    component's state, labelled with the indicator's name; the same indicator as the verdict
    table), every detection margin (black dots) and every isolation-evidence margin (open
    diamonds); log scale, alarm line at margin 1."""
    rows = margin_rows(verdict)
    if not any(r.detection or r.evidence for r in rows):
        return None
    fig, ax = _axes((10, 0.35 * len(rows) + 1.2))
    for i, r in enumerate(rows):
        if math.isfinite(r.worst_margin) and r.worst_margin > 0:
            ax.barh(i, r.worst_margin, color=STATE_COLOURS.get(r.state, "0.7"), alpha=0.6)
            ax.annotate(f" {r.worst}", (r.worst_margin, i), va="center", fontsize=6)
        if r.detection:
            ax.plot(r.detection, np.full(len(r.detection), i), "k.", ms=3)
        if r.evidence:
            ax.plot(r.evidence, np.full(len(r.evidence), i), "D", ms=4, mfc="none",
                    mec="tab:purple")
    ax.axvline(1.0, color="k", lw=0.8, ls="--", label="threshold (margin 1)")
    ax.plot([], [], "k.", ms=3, label="detection indicator")
    ax.plot([], [], "D", ms=4, mfc="none", mec="tab:purple", label="isolation evidence")
    ax.set_xscale("log")
    ax.set_yticks(range(len(rows)), [f"{r.component} ({r.state})" for r in rows], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("margin value/threshold [-]")
    ax.set_title("Indicator margins per component (bar: worst detection indicator, named)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=7)
    return fig


def kurtogram_figure(kurtogram: xr.DataArray) -> Any | None:
    """Kurtogram (spectral kurtosis over frequency band and level), if two-dimensional."""
    if kurtogram is None or kurtogram.ndim != 2:
        return None
    ydim, xdim = kurtogram.dims
    fig, ax = _axes((10, 3))
    mesh = ax.pcolormesh(kurtogram[xdim].values, kurtogram[ydim].values, kurtogram.values,
                         shading="auto", cmap="magma")
    fig.colorbar(mesh, ax=ax, label=f"spectral kurtosis [{_units(kurtogram, '-')}]")
    ax.set_xlabel(f"{xdim} [{_units(kurtogram[xdim], '-')}]")
    ax.set_ylabel(f"{ydim} [{_units(kurtogram[ydim], '-')}]")
    ax.set_title("Kurtogram (envelope band choice)")
    return fig


# ---------------------------------------------------------------- sections
def _section(title: str, *parts: str) -> str:
    return f"<section><h2>{html.escape(title)}</h2>{''.join(parts)}</section>"


def _probability(p: Any) -> str:
    try:
        v = float(p)
    except (TypeError, ValueError):
        return "–"
    return f"{v:.3g}" if math.isfinite(v) else "–"


def detection_section(verdict: Verdict) -> str:
    """The machine-level answers of a verdict that carries them: ``detection`` (fault detected
    or not, false-alarm probability over its tests, alarms) and ``localisation`` (state
    localised / uncertain / none, components, confidence, ranked candidates with their
    evidence and the score's meaning). Empty when the verdict has neither (dicts only)."""
    det = getattr(verdict, "detection", None)
    loc = getattr(verdict, "localisation", None)
    parts: list[str] = []
    if isinstance(det, dict):
        detected = bool(det.get("detected", False))
        head = ("Fault detected." if detected else "No fault detected.")
        parts.append(f'<p class="{"detected" if detected else "clear"}"><b>Detection: '
                     f"{html.escape(head)}</b></p>")
        parts.append(_note(
            f"Machine false-alarm probability {_probability(det.get('false_alarm_probability'))}"
            f" over {_fmt(det.get('tests', '–'))} tests (per test α = "
            f"{_probability(det.get('alpha_per_test'))})."))
        alarms = pd.DataFrame(list(det.get("alarms") or []),
                              columns=["component", "indicator", "margin"])
        if len(alarms):
            parts.append(html_table(alarms, {"component": "component", "indicator": "indicator",
                                             "margin": "margin value/threshold [-]"}))
    if isinstance(loc, dict):
        state = str(loc.get("state", "none"))
        names = [str(c) for c in loc.get("components") or []]
        if not names and state == "uncertain":
            names = [str(c.get("component", "")) for c in loc.get("candidates") or []
                     if isinstance(c, dict)]
        comps = ", ".join(n for n in names if n) or "none"
        text = {"localised": f"Localised to {comps}",
                "uncertain": f"Location uncertain; candidates {comps}",
                "none": "Not localised"}.get(state, f"{state}: {comps}")
        cls = {"localised": "detected", "uncertain": "uncertain"}.get(state, "clear")
        parts.append(f'<p class="{cls}"><b>Localisation: {html.escape(text)} (confidence '
                     f"{html.escape(_probability(loc.get('confidence')))}).</b></p>")
        cands = pd.DataFrame(list(loc.get("candidates") or []),
                             columns=["component", "posterior", "evidence", "value",
                                      "threshold"])
        if len(cands):
            parts.append(html_table(cands, {"component": "component", "posterior": "posterior",
                                            "evidence": "evidence", "value": "value",
                                            "threshold": "threshold"}))
        if loc.get("score"):
            parts.append(_note(f"Score: {loc['score']}"))
    return _section("Detection and localisation", *parts) if parts else ""


def verdict_section(verdict: Verdict) -> str:
    """Per-component verdict table (state cells coloured: alarm, uncertain, healthy,
    unknown) and the summary line."""
    df = verdict.table()
    states = list(df["state"])
    headers = {"component": "component", "kind": "kind", "state": "state",
               "worst_indicator": "worst indicator", "margin": "margin value/threshold [-]",
               "isolation": "isolation evidence", "isolation_margin": "evidence margin [-]"}
    table = html_table(df, headers, lambda i, c: states[i] if c == "state" else "")
    s = verdict.summary()
    alarms = list(s.get("alarms") or [])
    uncertain = [n for n, c in verdict.components.items() if c.state == "uncertain"]
    line = (f"Alarm on: {', '.join(alarms)}." if alarms else "No component in alarm.")
    if uncertain:
        line += f" Uncertain (detected, not localised): {', '.join(uncertain)}."
    if "localised" in s:
        exp = ", ".join(s.get("expected") or []) or "none (healthy machine)"
        line += f" Configured fault(s) on: {exp}; "
        line += "alarms match the configured faults." if s["localised"] else (
            f"missed: {', '.join(s.get('missed') or []) or 'none'}, "
            f"unexpected: {', '.join(s.get('unexpected') or []) or 'none'}.")
    notes = "".join(f"<li>{html.escape(n)}</li>" for n in verdict.notes)
    chart = margin_figure(verdict)
    return _section("Verdict", f"<p><b>{html.escape(line)}</b></p>", table,
                    *(_figures([("margins per component", chart)]) if chart else []),
                    _note(verdict.rule.describe()),
                    f"<p>Notes (components not analysed, isolation):</p><ul>{notes}</ul>"
                    if notes else "")


def machine_section(verdict: Verdict) -> str:
    """Machine, channels, baseline and record, configured faults."""
    items = [("machine", verdict.machine), ("channel(s)", ", ".join(verdict.channels)),
             ("threshold rule", verdict.rule.describe())]
    items += [it for k, v in verdict.baseline.items()
              if (it := _setting("baseline", k, v)) is not None]
    items += [it for k, v in verdict.record.items()
              if (it := _setting("record", k, v)) is not None]
    dl = "".join(f"<tr><th class=\"txt\">{html.escape(k)}</th><td class=\"txt\">"
                 f"{html.escape(str(v))}</td></tr>" for k, v in items)
    if verdict.expected_faults is None:
        faults = _note("Configured faults: not known (measured record).")
    elif not verdict.expected_faults:
        faults = "<p>Configured faults: none (healthy machine).</p>"
    else:
        faults = "<p>Configured faults (expected alarm locations):</p><ul>" + "".join(
            f"<li><b>{html.escape(f.component)}</b> ({html.escape(f.kind)}): "
            f"{html.escape(f.description)} <code>{html.escape(f.field)}</code></li>"
            for f in verdict.expected_faults) + "</ul>"
    return _section("Machine and configured faults", f"<table>{dl}</table>", faults)


def kinematics_section(freqs: CharacteristicFrequencies | None) -> str:
    """The kinematic tables at the record's operating point."""
    if freqs is None:
        return _section("Kinematics", _note("No operating point: kinematic tables left out."))
    speeds = ", ".join(f"{k} {v:.4g} rpm" for k, v in freqs.inputs_rpm.items())
    parts = [f"<p>Input speeds: {html.escape(speeds)}; orders are events "
             f"per revolution of <b>{html.escape(freqs.order_reference)}</b> "
             f"({freqs.reference_hz:.5g} Hz).</p>"]
    for attr, title, headers in KINEMATIC_TABLES:
        df: pd.DataFrame = getattr(freqs, attr)
        if not df.empty:
            parts.append(f"<h3>{html.escape(title)}</h3>" + html_table(df, headers))
    return _section("Kinematics", *parts)


def indicator_section(verdict: Verdict, channel_units: str | None = None) -> str:
    """All judged indicators with their unit, baseline statistics and thresholds; alarms
    highlighted. A level in the analysed channel's unit shows that unit (``channel_units``,
    e.g. m/s²) when the channel states it."""
    df = verdict.indicator_table()
    if df.empty:
        return _section("Indicators and thresholds", _note("No indicator could be judged."))
    units = [_unit_of(k) for k in df["indicator"]]
    if channel_units:
        units = [channel_units if u == "channel units" else u for u in units]
    df = df.assign(unit=units)
    alarms = list(df["alarm"])
    headers = dict(INDICATOR_COLUMNS)
    table = html_table(df, headers,
                       lambda i, c: "alarm" if alarms[i] and c in ("value", "margin") else "")
    return _section("Indicators and thresholds", table, _note(
        "Record value: median over the record's blocks of whole revolutions; baseline mean and "
        "std pooled over every block of every baseline record; threshold = mean + k·σ (two-sided"
        " indicators: |value − mean| > k·σ, margin = |value − mean|/(k·σ))."))


def _channel_units(ds: xr.Dataset | None, channel: str | None) -> str | None:
    """The stated unit of the analysed channel of a result (None when unknown)."""
    if ds is None or not channel or f"sensors.{channel}" not in ds:
        return None
    unit = str(ds[f"sensors.{channel}"].attrs.get("units", "")).strip()
    return unit or None


def _unit_of(name: str) -> str:
    ind = explain(name)
    return ind.unit if ind is not None else "?"


def shown_indicators(verdict: Verdict) -> list[str]:
    """Indicator names (``channel:`` prefix dropped) shown in the verdict and indicator
    tables, first-seen order."""
    names: list[str] = []
    for c in verdict.components.values():
        for k in c.indicators:
            key = str(k).rpartition(":")[2]
            if key not in names:
                names.append(key)
    for key in list(verdict.table()["worst_indicator"]) + list(verdict.table()["isolation"]):
        key = str(key).rpartition(":")[2]
        if key and key not in names:
            names.append(key)
    return names


def explanations_section(verdict: Verdict) -> str:
    """What every indicator shown in the tables means: definition, unit, direction and
    reference (:mod:`geardyn.diagnosis.explain`; also docs/indicators.md)."""
    names = shown_indicators(verdict)
    if not names:
        return ""
    rows = []
    for n in names:
        ind = explain(n)
        if ind is None:
            rows.append({"name": n, "definition": "no explanation registered", "unit": "?",
                         "direction": "", "reference": ""})
        else:
            rows.append({"name": n, "definition": ind.definition, "unit": ind.unit,
                         "direction": "upper" if ind.higher_is_worse else "two-sided",
                         "reference": ind.reference})
    df = pd.DataFrame(rows, columns=["name", "definition", "unit", "direction", "reference"])
    table = html_table(df, {"name": "indicator", "definition": "definition", "unit": "unit",
                            "direction": "alarm direction", "reference": "reference"},
                       lambda i, c: "def" if c in ("definition", "reference") else "")
    return _section("Indicators", table, _note(
        "Unit 1: dimensionless; channel units: the unit of the analysed channel. Direction "
        "upper: alarm above the threshold; two-sided: alarm outside the baseline band. The "
        "full list is in docs/indicators.md."))


def _figures(items: Iterable[tuple[str, Any]]) -> list[str]:
    return [_img(fig, alt) if fig is not None else _note(f"{alt}: not available")
            for alt, fig in items]


def _band_note(band: SensorBand, reference: str) -> str:
    ref = reference or "the reference"
    text = (f"Orders of {ref} at the record's mean speed ({band.reference_hz:.4g} Hz); drawn up "
            f"to order {band.order_max:.4g} ({band.order_max * band.reference_hz:.4g} Hz)")
    if math.isfinite(band.nyquist_order):
        text += f", the channel's Nyquist order being {band.nyquist_order:.4g}"
    if band.modes_hz:
        text += "; transfer-path mode(s) at " + ", ".join(
            f"{f:.4g} Hz (order {o:.4g})" for f, o in zip(band.modes_hz, band.modes_order,
                                                         strict=True))
    text += "."
    if band.truncated:
        text += (f" The analysed spectrum stops at order {band.analysed_order:.4g}, below the "
                 "channel's Nyquist order (angular resampling limit): content above it is not "
                 "shown.")
    return _note(text)


def spectra_section(record: Features, healthy: Features | None,
                    freqs: CharacteristicFrequencies | None,
                    sampling: tuple[float | None, tuple[float, ...]] = (None, ())) -> str:
    """Order spectrum over the sensor's band (:func:`sensor_band`, ``sampling`` = sample rate
    [Hz] and transfer-path modes [Hz] of the channel) and zoomed on the meshes (annotated),
    envelope spectrum (record against healthy)."""
    parts: list[str] = []
    markers = getattr(record, "markers", None)
    spec = getattr(record, "order_spectrum", None)
    f_ref = _reference_hz(record, freqs)
    if spec is not None:
        hspec = getattr(healthy, "order_spectrum", None)
        reference = str(getattr(record, "reference", "") or
                        (freqs.order_reference if freqs is not None else ""))
        if f_ref is not None:
            band = sensor_band(float(spec[spec.dims[0]].values[-1]), f_ref, *sampling)
            parts += _figures([("order spectrum over the sensor band",
                                sensor_band_figure(spec, hspec, band, markers, reference))])
            parts.append(_band_note(band, reference))
        fig = order_spectrum_figure(spec, hspec, markers, _mesh_xmax(freqs, spec),
                                    "Order spectrum around the meshes (record)")
        parts += _figures([("order spectrum around the meshes", fig)])
    env = getattr(record, "envelope_spectrum", None)
    if env is not None:
        lines = None
        if markers is not None and len(markers):
            lines = markers[markers["kind"].isin(["bearing", "fault", "shaft", "planet_pass"])]
        top = float(env[env.dims[0]].values[-1])
        xmax = min(top, 1.2 * float(lines["order"].max())) if lines is not None and len(
            lines) else top
        fig = order_spectrum_figure(env, getattr(healthy, "envelope_spectrum", None), lines,
                                    xmax, "Envelope spectrum (record)")
        band = getattr(record, "band", None)
        parts += _figures([("envelope spectrum", fig)])
        if band is not None:
            ref = getattr(record, "reference", "") or "the reference"
            parts.append(_note(f"Envelope band: orders {_fmt(band[0])} to {_fmt(band[1])} "
                               f"(events per revolution of {ref})"))
    kg = getattr(record, "kurtogram", None)
    if kg is not None:
        parts += _figures([("kurtogram", kurtogram_figure(kg))])
    return _section("Spectra", *parts) if parts else ""


def tsa_section(record: Features, healthy: Features | None, verdict: Verdict) -> str:
    """TSA of every component (record with the healthy baseline behind)."""
    tsas: dict[str, xr.DataArray] = getattr(record, "tsa", None) or {}
    base: dict[str, xr.DataArray] = getattr(healthy, "tsa", None) or {}
    figs = []
    for comp, da in tsas.items():
        state = verdict.components.get(comp)
        figs.append((f"TSA of {comp} ({state.state if state else 'not judged'})",
                     tsa_figure(comp, da, base.get(comp))))
    return _section("Time-synchronous averages", *_figures(figs)) if figs else ""


def time_frequency_section(ds: xr.Dataset | None, channel: str | None, record: Features,
                           verdict: Verdict, resolve_hz: float | None, teeth: dict[str, int],
                           modes_hz: Sequence[float] = ()) -> str:
    """Spectrogram of the record channel up to its Nyquist frequency (bins of at most
    ``resolve_hz``, modes marked) and CWT of the TSA of the worst component."""
    parts = []
    if ds is not None and channel:
        fig = spectrogram_figure(ds, channel, None, resolve_hz, modes_hz)
        parts += _figures([(f"spectrogram of {channel}", fig)])
    tsas: dict[str, xr.DataArray] = getattr(record, "tsa", None) or {}
    worst = _worst_component(verdict, tsas)
    if worst is not None:
        z = teeth.get(worst, 0)
        max_order = 3.3 * z if z else tsas[worst].size / 4
        parts += _figures([(f"CWT of the TSA of {worst}",
                            cwt_figure(worst, tsas[worst], max_order))])
    return _section("Time–frequency", *parts) if parts else ""


def _worst_component(verdict: Verdict, names: Sequence[str]) -> str | None:
    best, best_m = None, -math.inf
    for name in names:
        c = verdict.components.get(name)
        w = c.worst if c is not None else None
        if w is not None and w[1] > best_m:
            best, best_m = name, w[1]
    return best if best is not None else (next(iter(names), None))


# ---------------------------------------------------------------- page
def write_report(
    out_dir: str | Path,
    verdict: Verdict,
    record: Features,
    *,
    healthy: Features | None = None,
    freqs: CharacteristicFrequencies | None = None,
    record_ds: xr.Dataset | None = None,
    channel: str | None = None,
    title: str | None = None,
    modes_hz: Sequence[float] | None = None,
) -> Path:
    """Write ``out_dir/report.html`` and return its path.

    ``record`` / ``healthy``: features of the judged record and of one healthy baseline record
    (drawn behind the record); ``freqs``: kinematics at the record's operating point;
    ``record_ds`` + ``channel``: the record result and its analysed channel (spectrogram; its
    sample rate bounds the drawn order range, its ``transfer_modes_hz`` are marked);
    ``modes_hz``: transfer-path mode frequencies [Hz] to mark instead (e.g. from a config).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    teeth: dict[str, int] = {}
    resolve_hz = None
    if freqs is not None and not freqs.wheels.empty:
        teeth = {str(w): int(z) for w, z in zip(freqs.wheels["wheel"], freqs.wheels["teeth"],
                                                strict=True)}
    if freqs is not None and not freqs.meshes.empty:
        mesh = np.abs(np.asarray(freqs.meshes["mesh_hz"], float))
        mesh = mesh[np.isfinite(mesh) & (mesh > 0)]
        resolve_hz = 0.5 * float(mesh.min()) if mesh.size else None
    fs, modes = channel_sampling(record_ds, channel)
    if modes_hz is not None:
        modes = tuple(float(f) for f in modes_hz)
    title = title or f"geardyn diagnosis: {verdict.machine}"
    body = [
        f"<h1>{html.escape(title)}</h1>",
        detection_section(verdict),
        verdict_section(verdict),
        machine_section(verdict),
        kinematics_section(freqs),
        spectra_section(record, healthy, freqs, (fs, modes)),
        tsa_section(record, healthy, verdict),
        time_frequency_section(record_ds, channel, record, verdict, resolve_hz, teeth, modes),
        indicator_section(verdict, _channel_units(record_ds, channel)),
        explanations_section(verdict),
    ]
    page = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{html.escape(title)}</title><style>{_CSS}</style></head><body>"
            + "\n".join(b for b in body if b) + "</body></html>\n")
    path = out / "report.html"
    write_text(path, page)
    return path
