"""Matplotlib figures of the diagnosis signals (annotated order/frequency spectrum, spectrogram,
waterfall, TSA, cepstrum).

Each function takes ``ax=None`` and returns the figure; nothing is shown, saved or switched
here (see :mod:`geardyn.plotting`). Axes are labelled with units from the coordinates' attrs;
``units`` gives the signal's own unit (e.g. ``"m/s²"``, ``"rad/s"``) for amplitude axes and
dB colour bars. Range options (``xmax``, ``ymax``, ``qmax``) set the axis limits.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
import xarray as xr

from geardyn.plotting import axis_label, db_label, labelled_colorbar, new_axes, unit_text
from geardyn.signal.annotate import _COLORS as MARKER_COLORS
from geardyn.signal.annotate import KINDS, annotate_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: legend entry of each marker family
FAMILY_NAMES = {
    "shaft": "shaft orders",
    "mesh": "mesh orders",
    "sideband": "mesh sidebands",
    "bearing": "bearing lines",
    "fault": "tooth-fault lines",
    "planet_pass": "planet pass",
    "planet_dominant": "dominant planet-pass lines",
}
#: families labelled first when labels would collide (sidebands are never labelled)
_LABEL_PRIORITY = ("mesh", "fault", "bearing", "planet_dominant", "planet_pass", "shaft")
_SIGNAL_UNITS = "signal units"
#: Most points of one spectrum curve drawn; a longer one is drawn as the minimum and maximum of
#: each of ``MAX_CURVE_POINTS/2`` bins (:func:`curve_points`).
MAX_CURVE_POINTS = 20000


def curve_points(
    x: np.ndarray,
    y: np.ndarray,
    lo: float | None = None,
    hi: float | None = None,
    max_points: int = MAX_CURVE_POINTS,
    log_x: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """The points of a curve ``y(x)`` (``x`` increasing) within ``[lo, hi]`` to draw: all of
    them up to ``max_points``, else the minimum and maximum of ``y`` over each of
    ``max_points/2`` bins of ``x`` (equal in ``log x`` if ``log_x``), drawn at the bin's centre:
    at a few thousand pixels across the same picture — every peak and floor kept — without
    drawing millions of points."""
    xs = np.asarray(x, float)
    ys = np.asarray(y, float)
    i = 0 if lo is None else int(np.searchsorted(xs, lo, side="left"))
    j = xs.size if hi is None else int(np.searchsorted(xs, hi, side="right"))
    if j - i <= max_points:
        return xs[i:j], ys[i:j]
    xs, ys = xs[i:j], ys[i:j]
    nb = max(1, max_points // 2)
    if log_x and xs[0] > 0:
        cuts = np.geomspace(xs[0], xs[-1], nb + 1)[1:-1]
        edges = np.unique(np.concatenate([[0], np.searchsorted(xs, cuts), [xs.size]]))
    else:
        edges = np.unique(np.linspace(0, xs.size, nb + 1).astype(int))
    starts = edges[:-1]
    mid = 0.5 * (xs[starts] + xs[edges[1:] - 1])
    out_x = np.repeat(mid, 2)
    out_y = np.empty(out_x.size)
    out_y[0::2] = np.maximum.reduceat(ys, starts)
    out_y[1::2] = np.minimum.reduceat(ys, starts)
    return out_x, out_y


def _units(da: xr.DataArray, units: str | None) -> str:
    return str(units if units is not None else da.attrs.get("units", _SIGNAL_UNITS))


def _spectrum_ylim(x: np.ndarray, y: np.ndarray, lo: float, hi: float, log: bool,
                   ymax: float | None) -> tuple[float, float] | None:
    """Limits of the amplitude axis from the part of the spectrum on show."""
    inside = y[(x >= lo) & (x <= hi)]
    pos = inside[inside > 0] if log else inside
    if not pos.size:
        return None if ymax is None else (0.0 if not log else ymax * 1e-6, ymax)
    top = ymax if ymax is not None else (pos.max() * 3 if log else pos.max() * 1.1)
    bottom = max(pos.min(), top * 1e-6) if log else min(0.0, pos.min())
    return bottom, top


def draw_markers(ax: Axes, markers: pd.DataFrame, unit: str = "order",
                 kinds: Iterable[str] | None = None, label: bool = True,
                 max_labels: int = 40, fontsize: float = 6.0) -> list[str]:
    """Marker lines of :func:`~geardyn.signal.annotate.annotate_axes` with one legend entry per
    family shown (outside the axes, right) and text labels that do not overlap: labels closer
    than 1.5 font sizes to an already placed one (or to the left edge) are dropped, mesh
    lines placed first.

    Returns the families drawn (those with a marker inside the x limits).
    """
    import matplotlib.lines as mlines

    wanted = list(KINDS if kinds is None else kinds)
    annotate_axes(ax, markers, unit=unit, kinds=wanted, label=False)
    lo, hi = ax.get_xlim()
    sel = markers[markers["kind"].isin(wanted) & markers[unit].between(lo, hi)]
    shown = [k for k in KINDS if k in set(sel["kind"])]
    if label:
        _marker_labels(ax, sel, unit, max_labels, fontsize)
    if shown:
        handles = [mlines.Line2D([], [], color=MARKER_COLORS[k], ls="--", lw=0.9,
                                 label=FAMILY_NAMES[k]) for k in shown]
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7,
                  title="markers", title_fontsize=7, frameon=False)
    return shown


def _marker_labels(ax: Axes, sel: pd.DataFrame, unit: str, max_labels: int,
                   fontsize: float) -> None:
    fig = ax.figure
    fig.draw_without_rendering()  # final layout first, so that pixel distances hold
    height = 1.25 * fontsize * fig.dpi / 72.0  # a rotated label's width (line height), px
    gap = 1.2 * height
    left = ax.get_window_extent().x0 + height  # labels sit left of their line (ha="right")
    y0 = ax.get_ylim()[1]
    placed: list[float] = []
    for kind in _LABEL_PRIORITY:
        for _, r in sel[sel["kind"] == kind].iterrows():
            if len(placed) >= max_labels:
                return
            px = float(ax.transData.transform((r[unit], y0))[0])
            if px < left or any(abs(px - p) < gap for p in placed):
                continue
            placed.append(px)
            ax.text(r[unit], 0.99, r["label"], transform=ax.get_xaxis_transform(),
                    rotation=90, fontsize=fontsize, va="top", ha="right",
                    color=MARKER_COLORS[kind])


def plot_spectrum(
    spec: xr.DataArray,
    markers: pd.DataFrame | None = None,
    xmax: float | None = None,
    title: str = "",
    log: bool = True,
    *,
    ymax: float | None = None,
    units: str | None = None,
    kinds: Iterable[str] | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Amplitude (order or frequency) spectrum, optionally annotated with the marker table of
    :func:`~geardyn.signal.annotate.spectral_markers` (one legend entry per family).

    ``xmax`` [orders or Hz] and ``ymax`` [``units``] set the axis limits (x from 0);
    ``units`` is the signal's unit (default ``spec.attrs['units']``); ``kinds`` selects
    marker families.
    """
    dim = spec.dims[0]
    fig, ax = new_axes(ax)
    x = spec[dim].values
    y = spec.values
    hi = xmax if xmax is not None else float(x[-1])
    ax.plot(*curve_points(x, y, None, hi), lw=0.6, color="0.2")
    ax.set_xlim(0, hi)
    if log:
        ax.set_yscale("log")
    lim = _spectrum_ylim(x, y, 0.0, hi, log, ymax)
    if lim is not None:
        ax.set_ylim(*lim)
    ax.set_xlabel(axis_label(spec[dim], str(dim)))
    ax.set_ylabel(f"{spec.attrs.get('long_name', 'amplitude')} {unit_text(_units(spec, units))}")
    ax.set_title(title)
    if markers is not None and len(markers):
        draw_markers(ax, markers, unit="order" if dim == "order" else "hz", kinds=kinds)
    return fig


def _position_label(c: xr.DataArray, speed: bool) -> str:
    """Label of a map's position axis: speed (rpm unless stated), time or angle."""
    if speed:
        return axis_label(c, "speed", c.attrs.get("units", "rpm"))
    return axis_label(c, str(c.name))


def plot_map(
    m: xr.DataArray,
    ymax: float | None = None,
    title: str = "",
    *,
    xmax: float | None = None,
    units: str | None = None,
    db_range: float = 100.0,
    ax: Axes | None = None,
) -> Figure:
    """Spectrogram / order map (dims ``(frequency|order, time|angle)``) in dB re 1 ``units``,
    against ``speed`` when the map has an increasing ``speed`` coordinate.

    ``ymax`` [Hz or orders] and ``xmax`` [s, rev or rpm] set the axis limits; the colour scale
    spans ``db_range`` dB below the maximum.
    """
    fig, ax = new_axes(ax)
    ydim, xdim = m.dims
    use_speed = "speed" in m.coords and bool(np.all(np.diff(m["speed"].values) > 0))
    xc = m["speed"] if use_speed else m[xdim]
    db = 20 * np.log10(np.maximum(m.values, 1e-300))
    top = float(np.max(db))
    mesh = ax.pcolormesh(xc.values, m[ydim].values, db, shading="auto", cmap="viridis",
                         vmin=top - db_range, vmax=top)
    ax.set_ylim(0, ymax if ymax is not None else m[ydim].values[-1])
    if xmax is not None:
        ax.set_xlim(right=xmax)
    ax.set_xlabel(_position_label(xc, use_speed))
    ax.set_ylabel(axis_label(m[ydim], str(ydim)))
    ax.set_title(title)
    labelled_colorbar(mesh, ax, db_label(str(m.attrs.get("long_name", "amplitude")),
                                   _units(m, units)))
    return fig


def plot_tsa(avg: np.ndarray, title: str = "", *, units: str | None = None,
             ax: Axes | None = None) -> Figure:
    """One revolution of a TSA against shaft angle [deg]."""
    fig, ax = new_axes(ax)
    ax.plot(np.arange(avg.size) * 360.0 / avg.size, avg, lw=0.8)
    ax.set_xlim(0, 360)
    ax.set_xlabel("shaft angle [deg]")
    ax.set_ylabel(f"synchronous average {unit_text(units or _SIGNAL_UNITS)}")
    ax.set_title(title)
    return fig


def plot_cepstrum(cep: xr.DataArray, qmax: float | None = None, title: str = "", *,
                  quefrency_units: str | None = None, ax: Axes | None = None) -> Figure:
    """Cepstrum against quefrency (skip the zero-quefrency bins); ``qmax`` sets the x limit.

    Quefrency is in units of 1/``fs`` of the cepstrum (s for a time signal, rev for an angle
    signal with ``fs`` = samples per revolution): ``quefrency_units`` names it (default: the
    coordinate's ``units`` attr, else ``1/fs``).
    """
    fig, ax = new_axes(ax)
    q = cep["quefrency"].values
    n = max(1, q.size // 1000)
    ax.plot(q[n : q.size // 2], cep.values[n : q.size // 2], lw=0.6)
    if qmax is not None:
        ax.set_xlim(0, qmax)
    qu = quefrency_units or cep["quefrency"].attrs.get("units", "1/fs")
    ax.set_xlabel(f"quefrency {unit_text(qu)}")
    ax.set_ylabel(axis_label(cep, str(cep.name or "cepstrum")))
    ax.set_title(title)
    return fig


def plot_waterfall(
    m: xr.DataArray,
    n_lines: int = 20,
    ymax: float | None = None,
    title: str = "",
    *,
    ax: Axes | None = None,
) -> Figure:
    """Waterfall: up to ``n_lines`` spectra of a map (dims ``(order|frequency, angle|time)``),
    each offset vertically by its speed [rpm] (if a ``speed`` coordinate exists) or position.
    ``ymax`` [orders or Hz] is the largest order/frequency shown (the x axis here)."""
    fig, ax = new_axes(ax, (8, 6))
    ydim, xdim = m.dims
    idx = np.unique(np.linspace(0, m.sizes[xdim] - 1, min(n_lines, m.sizes[xdim])).astype(int))
    pc = m["speed"] if "speed" in m.coords else m[xdim]
    pos = pc.values
    span = float(np.ptp(pos[idx])) or 1.0
    scale = 0.8 * span / max(len(idx), 1) / (float(m.max()) or 1.0)
    x = m[ydim].values
    for i in idx[::-1]:
        ax.fill_between(x, pos[i], pos[i] + scale * m.values[:, i], color="white", lw=0)
        ax.plot(x, pos[i] + scale * m.values[:, i], lw=0.6, color="k")
    ax.set_xlim(0, ymax if ymax is not None else x[-1])
    ax.set_xlabel(axis_label(m[ydim], str(ydim)))
    ax.set_ylabel(_position_label(pc, "speed" in m.coords))
    ax.set_title(title)
    return fig
