"""The diagnosis report: one self-contained HTML page (``report.html``).

Sections: verdict (table, margin chart, notes); machine, record, baseline and configured
faults; kinematic tables (shaft speeds, meshes, wheel fault orders, bearing orders, planet
pass); annotated order spectrum (healthy baseline against the record); envelope spectrum with
the bearing and fault lines (and the kurtogram of the band choice); TSA per component;
spectrogram of the channel and CWT of the TSA of the worst component; indicator table with
thresholds (alarm cells highlighted). Figures are embedded as PNG data URIs; the page
has no external file, stylesheet or script.

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
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr

from geardyn.checkpoint import write_text
from geardyn.diagnosis.verdict import Verdict

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
td.unknown{background:#eee;color:#666}
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

#: Indicator table columns: (verdict.indicator_table column, header with unit).
INDICATOR_COLUMNS = (
    ("component", "component"), ("kind", "kind"), ("indicator", "indicator"),
    ("value", "record value [-]"), ("mean", "baseline mean [-]"), ("std", "baseline std [-]"),
    ("threshold", "threshold [-]"), ("margin", "margin value/threshold [-]"),
)


# ---------------------------------------------------------------- HTML building blocks
def _fmt(v: Any) -> str:
    if isinstance(v, bool | np.bool_):
        return "yes" if v else "no"
    if isinstance(v, float | np.floating):
        return "–" if not math.isfinite(float(v)) else f"{float(v):.4g}"
    return str(v)


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


def _order_xmax(freqs: CharacteristicFrequencies | None, spec: xr.DataArray) -> float:
    top = float(spec[spec.dims[0]].values[-1])
    if freqs is None or freqs.meshes.empty:
        return top
    return min(top, 3.3 * float(freqs.meshes["mesh_order"].max()))


def order_spectrum_figure(
    record: xr.DataArray,
    healthy: xr.DataArray | None,
    markers: pd.DataFrame | None,
    xmax: float,
    title: str,
) -> Any:
    """Record order spectrum (annotated) with the healthy baseline's behind it."""
    from geardyn.signal.plots import plot_spectrum

    fig = plot_spectrum(record, markers, xmax, title)
    ax = fig.axes[0]
    ax.lines[0].set_label("record")
    if healthy is not None:
        dim = healthy.dims[0]
        ax.plot(healthy[dim].values, healthy.values, lw=0.6, color="tab:cyan", alpha=0.8,
                label="healthy baseline", zorder=1)
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
    ``max_order`` (seed 004 ch. 9 localises a tooth fault this way). The TSA is periodic: it
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


def spectrogram_figure(ds: xr.Dataset, channel: str, fmax: float | None) -> Any | None:
    """STFT (time-sampled channel) or angular spectrogram (angle-sampled channel) in dB, up to
    ``fmax`` [Hz] (segments resolve fmax/30, at least 4 segments in the record)."""
    from geardyn.results import channel as get_channel
    from geardyn.signal import angular_spectrogram, stft
    from geardyn.signal.plots import plot_map

    ch = get_channel(ds, channel)
    if ch.sampling == "time" and ch.values.size >= 64:
        fs = ch.sample_rate_hz or 1.0 / float(np.median(np.diff(ch.time)))
        want = fs / (fmax / 30.0) if fmax else fs
        nper = int(2 ** math.ceil(math.log2(max(16.0, want))))
        nper = min(nper, int(2 ** math.floor(math.log2(max(16, ch.values.size // 4)))))
        m = stft(ch.values - ch.values.mean(), fs, nperseg=nper)
        m.attrs["units"] = ch.units
        ymax = min(fs / 2, fmax) if fmax else None
        fig = plot_map(m, ymax=ymax, title=f"Spectrogram of {channel}")
        fig.axes[0].set_ylabel("frequency [Hz]")
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


_STATE_COLOURS = {"alarm": "tab:red", "healthy": "tab:green", "unknown": "0.7"}


def margin_figure(verdict: Verdict) -> Any | None:
    """Horizontal bars: every indicator margin of each component (dots) and its worst one
    (bar, coloured by the component's state), log scale, alarm line at margin 1."""
    rows = [(name, c) for name, c in verdict.components.items()]
    if not any(c.indicators for _, c in rows):
        return None
    fig, ax = _axes((10, 0.35 * len(rows) + 1.2))
    for i, (_, c) in enumerate(rows):
        m = np.array([v.margin for v in c.indicators.values()], float)
        m = m[np.isfinite(m) & (m > 0)]
        if m.size:
            ax.barh(i, m.max(), color=_STATE_COLOURS[c.state], alpha=0.6)
            ax.plot(m, np.full(m.size, i), "k.", ms=3)
    ax.axvline(1.0, color="k", lw=0.8, ls="--", label="threshold (margin 1)")
    ax.set_xscale("log")
    ax.set_yticks(range(len(rows)), [f"{n} ({c.state})" for n, c in rows], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("margin value/threshold [-]")
    ax.set_title("Indicator margins per component (bar: worst; dots: every indicator)")
    ax.legend(loc="lower right", fontsize=7)
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


def verdict_section(verdict: Verdict) -> str:
    """Per-component verdict table (state cells coloured) and the summary line."""
    df = verdict.table()
    states = list(df["state"])
    headers = {"component": "component", "kind": "kind", "state": "state",
               "worst_indicator": "worst indicator", "margin": "margin value/threshold [-]",
               "isolation": "isolation evidence", "isolation_margin": "evidence margin [-]"}
    table = html_table(df, headers, lambda i, c: states[i] if c == "state" else "")
    s = verdict.summary()
    line = (f"Alarm on: {', '.join(s['alarms'])}." if s["alarms"]
            else "No component in alarm.")
    if "localised" in s:
        exp = ", ".join(s["expected"]) or "none (healthy machine)"
        line += f" Configured fault(s) on: {exp}; "
        line += "alarms match the configured faults." if s["localised"] else (
            f"missed: {', '.join(s['missed']) or 'none'}, "
            f"unexpected: {', '.join(s['unexpected']) or 'none'}.")
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
    items += [(f"baseline {k}", _fmt(v)) for k, v in verdict.baseline.items()]
    items += [(f"record {k}", _fmt(v)) for k, v in verdict.record.items()]
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
    parts = [f"<p>Input speeds {html.escape(_fmt(freqs.inputs_rpm))} rpm; orders are events "
             f"per revolution of <b>{html.escape(freqs.order_reference)}</b> "
             f"({freqs.reference_hz:.5g} Hz).</p>"]
    for attr, title, headers in KINEMATIC_TABLES:
        df: pd.DataFrame = getattr(freqs, attr)
        if not df.empty:
            parts.append(f"<h3>{html.escape(title)}</h3>" + html_table(df, headers))
    return _section("Kinematics", *parts)


def indicator_section(verdict: Verdict) -> str:
    """All judged indicators with baseline statistics and thresholds; alarms highlighted."""
    df = verdict.indicator_table()
    if df.empty:
        return _section("Indicators and thresholds", _note("No indicator could be judged."))
    alarms = list(df["alarm"])
    headers = dict(INDICATOR_COLUMNS)
    table = html_table(df, headers,
                       lambda i, c: "alarm" if alarms[i] and c in ("value", "margin") else "")
    return _section("Indicators and thresholds", table, _note(
        "Record value: median over the record's blocks of whole revolutions; baseline mean and "
        "std pooled over every block of every baseline record; threshold = mean + k·σ (two-sided"
        " indicators: |value − mean| > k·σ, margin = |value − mean|/(k·σ))."))


def _figures(items: Iterable[tuple[str, Any]]) -> list[str]:
    return [_img(fig, alt) if fig is not None else _note(f"{alt}: not available")
            for alt, fig in items]


def spectra_section(record: Features, healthy: Features | None,
                    freqs: CharacteristicFrequencies | None) -> str:
    """Annotated order spectrum and envelope spectrum (record against healthy)."""
    parts: list[str] = []
    markers = getattr(record, "markers", None)
    spec = getattr(record, "order_spectrum", None)
    if spec is not None:
        fig = order_spectrum_figure(spec, getattr(healthy, "order_spectrum", None), markers,
                                    _order_xmax(freqs, spec), "Order spectrum (record)")
        parts += _figures([("order spectrum", fig)])
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
            parts.append(_note(f"Envelope band: {_fmt(band)}"))
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
                           verdict: Verdict, fmax: float | None, teeth: dict[str, int]) -> str:
    """Spectrogram of the record channel and CWT of the TSA of the worst component."""
    parts = []
    if ds is not None and channel:
        parts += _figures([(f"spectrogram of {channel}", spectrogram_figure(ds, channel, fmax))])
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
) -> Path:
    """Write ``out_dir/report.html`` and return its path.

    ``record`` / ``healthy``: features of the judged record and of one healthy baseline record
    (drawn behind the record); ``freqs``: kinematics at the record's operating point;
    ``record_ds`` + ``channel``: the record result and its analysed channel (spectrogram).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    teeth: dict[str, int] = {}
    fmax = None
    if freqs is not None and not freqs.wheels.empty:
        teeth = {str(w): int(z) for w, z in zip(freqs.wheels["wheel"], freqs.wheels["teeth"],
                                                strict=True)}
    if freqs is not None and not freqs.meshes.empty:
        fmax = 3.3 * float(freqs.meshes["mesh_hz"].max())
    title = title or f"geardyn diagnosis: {verdict.machine}"
    body = [
        f"<h1>{html.escape(title)}</h1>",
        verdict_section(verdict),
        machine_section(verdict),
        kinematics_section(freqs),
        spectra_section(record, healthy, freqs),
        tsa_section(record, healthy, verdict),
        time_frequency_section(record_ds, channel, record, verdict, fmax, teeth),
        indicator_section(verdict),
    ]
    page = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{html.escape(title)}</title><style>{_CSS}</style></head><body>"
            + "\n".join(b for b in body if b) + "</body></html>\n")
    path = out / "report.html"
    write_text(path, page)
    return path
