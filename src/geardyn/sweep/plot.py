"""Detectability curves from a sweep data set: an indicator against fault severity, mean and
spread over seeds (seed 004 ch. 9 compares a handful of simulated cases by hand; a sweep gives
each point its scatter)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr

from geardyn.errors import InputError

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def detectability(ds: xr.Dataset, component: str, indicator: str, severity: str,
                  by: list[str] | None = None, healthy: dict[str, Any] | None = None
                  ) -> pd.DataFrame:
    """Indicator ``indicator`` of ``component`` (median over blocks) per ok case, grouped by
    the ``severity`` axis and the ``by`` axes: columns ``*by, severity, mean, std, n``
    (std with ddof = 1, NaN for one case). ``healthy``: axis values of the healthy cases
    (e.g. ``{"fault_gear": "none"}``); they join every curve of ``by[0]`` at their severity
    (typically 0)."""
    by = list(by or [])
    for name in [severity, *by, *(healthy or {})]:
        if name not in ds.coords:
            raise InputError(f"axis '{name}' is not in the data set (axes: "
                             f"{', '.join(ds.attrs.get('axes', '').strip('[]').split(','))})")
    if "indicators" not in ds:
        raise InputError("the data set has no indicators (outputs.indicators)")
    comps = [str(c) for c in ds["component"].values]
    names = [str(c) for c in ds["indicator"].values]
    if component not in comps:
        raise InputError(f"component '{component}' not in the data set ({', '.join(comps)})")
    if indicator not in names:
        raise InputError(f"indicator '{indicator}' not in the data set ({', '.join(names)})")
    vals = ds["indicators"].sel(component=component, indicator=indicator).median("block")
    frame = pd.DataFrame({k: np.asarray(ds[k].values) for k in [severity, *by]})
    frame["value"] = np.asarray(vals.values, float)
    frame = frame[np.asarray(ds["status"].values, dtype=object) == "ok"]
    if healthy and by:
        mask = np.ones(len(frame), bool)
        for k, v in healthy.items():
            mask &= frame[k].to_numpy() == v if k in frame else \
                np.asarray(ds[k].values)[frame.index] == v
        base = frame[mask]
        rest = frame[~mask]
        curves = [c for c in pd.unique(rest[by[0]])]
        copies = [base.assign(**{by[0]: c}) for c in curves]
        frame = pd.concat([rest, *copies], ignore_index=True)
    g = frame.groupby([*by, severity], sort=True)["value"]
    out = g.agg(mean="mean", std=lambda s: s.std(ddof=1), n="count").reset_index()
    return out


def plot_detectability(ds: xr.Dataset, component: str, indicator: str, severity: str,
                       by: list[str] | None = None, healthy: dict[str, Any] | None = None,
                       ax: Axes | None = None) -> Figure:
    """Figure of :func:`detectability`: mean ± one standard deviation over the cases of each
    point (seeds, replicates), one curve per value of ``by[0]``."""
    import matplotlib.pyplot as plt

    from geardyn.plotting import unit_text

    table = detectability(ds, component, indicator, severity, by, healthy)
    if ax is None:
        fig, ax = plt.subplots(figsize=(6, 4))
    else:
        fig = ax.figure
    groups = table.groupby(by[0], sort=False) if by else [("", table)]
    for name, t in groups:
        ax.errorbar(t[severity], t["mean"], yerr=t["std"].fillna(0.0), marker="o",
                    capsize=3, label=str(name) if by else None)
    units = str(ds[severity].attrs.get("units", ""))
    ax.set_xlabel(f"{severity} {unit_text(units)}")
    ax.set_ylabel(f"{indicator} of {component} [-]")
    ax.set_title(f"{indicator} of {component}: mean ± 1 std over seeds")
    if by:
        ax.legend(title=by[0])
    ax.grid(True, alpha=0.3)
    return fig
