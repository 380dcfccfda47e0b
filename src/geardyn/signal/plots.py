"""Matplotlib figures for the analysis report (order spectrum with annotations, spectrogram,
TSA, cepstrum). Each function returns the figure; nothing is shown or saved here."""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from geardyn.signal.annotate import annotate_axes


def _fig(figsize=(10, 4)):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt.subplots(figsize=figsize, constrained_layout=True)


def plot_spectrum(
    spec: xr.DataArray,
    markers: pd.DataFrame | None = None,
    xmax: float | None = None,
    title: str = "",
    log: bool = True,
) -> Any:
    """Amplitude (order or frequency) spectrum, optionally annotated with markers."""
    dim = spec.dims[0]
    fig, ax = _fig()
    x = spec[dim].values
    y = spec.values
    ax.plot(x, y, lw=0.6, color="0.2")
    if log:
        ax.set_yscale("log")
        pos = y[y > 0]
        if pos.size:
            ax.set_ylim(max(pos.min(), pos.max() * 1e-6), pos.max() * 3)
    ax.set_xlim(0, xmax if xmax is not None else x[-1])
    ax.set_xlabel("order [events/rev]" if dim == "order" else "frequency [Hz]")
    ax.set_ylabel("amplitude")
    ax.set_title(title)
    if markers is not None and len(markers):
        annotate_axes(ax, markers, unit="order" if dim == "order" else "hz")
    return fig


def plot_map(m: xr.DataArray, ymax: float | None = None, title: str = "") -> Any:
    """Spectrogram / order map (dims ``(frequency|order, time|angle)``) in dB."""
    fig, ax = _fig()
    ydim, xdim = m.dims
    use_speed = "speed" in m.coords and np.all(np.diff(m["speed"].values) > 0)
    xs = m["speed"].values if use_speed else m[xdim].values
    db = 20 * np.log10(np.maximum(m.values, m.values.max() * 1e-5 + 1e-300))
    ax.pcolormesh(xs, m[ydim].values, db, shading="auto", cmap="viridis")
    ax.set_ylim(0, ymax if ymax is not None else m[ydim].values[-1])
    unit = "s" if xdim == "time" else "rev"
    ax.set_xlabel("speed [rpm]" if use_speed else f"{xdim} [{unit}]")
    ax.set_ylabel("order" if ydim == "order" else "frequency [Hz]")
    ax.set_title(title)
    return fig


def plot_tsa(avg: np.ndarray, title: str = "") -> Any:
    """One revolution of a TSA against shaft angle [deg]."""
    fig, ax = _fig()
    ax.plot(np.arange(avg.size) * 360.0 / avg.size, avg, lw=0.8)
    ax.set_xlabel("shaft angle [deg]")
    ax.set_ylabel("TSA")
    ax.set_title(title)
    return fig


def plot_cepstrum(cep: xr.DataArray, qmax: float | None = None, title: str = "") -> Any:
    """Cepstrum against quefrency (skip the zero-quefrency bins)."""
    fig, ax = _fig()
    q = cep["quefrency"].values
    n = max(1, q.size // 1000)
    ax.plot(q[n : q.size // 2], cep.values[n : q.size // 2], lw=0.6)
    if qmax is not None:
        ax.set_xlim(0, qmax)
    ax.set_xlabel("quefrency")
    ax.set_title(title)
    return fig


def plot_waterfall(
    m: xr.DataArray, n_lines: int = 20, ymax: float | None = None, title: str = ""
) -> Any:
    """Waterfall: up to ``n_lines`` spectra of a map (dims ``(order|frequency, angle|time)``),
    each offset vertically by its speed [rpm] (if a ``speed`` coordinate exists) or position."""
    fig, ax = _fig((8, 6))
    ydim, xdim = m.dims
    idx = np.unique(np.linspace(0, m.sizes[xdim] - 1, min(n_lines, m.sizes[xdim])).astype(int))
    pos = m["speed"].values if "speed" in m.coords else m[xdim].values
    span = float(np.ptp(pos[idx])) or 1.0
    scale = 0.8 * span / max(len(idx), 1) / (float(m.max()) or 1.0)
    x = m[ydim].values
    for i in idx[::-1]:
        ax.fill_between(x, pos[i], pos[i] + scale * m.values[:, i], color="white", lw=0)
        ax.plot(x, pos[i] + scale * m.values[:, i], lw=0.6, color="k")
    ax.set_xlim(0, ymax if ymax is not None else x[-1])
    ax.set_xlabel("order" if ydim == "order" else "frequency [Hz]")
    ax.set_ylabel("speed [rpm]" if "speed" in m.coords else xdim)
    ax.set_title(title)
    return fig
