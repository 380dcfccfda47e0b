"""Warning and alarm levels of a trend, and the records that cross them.

Levels per (component, kind, indicator, channel) from healthy reference records (the first
``n`` of the trend, or simulated healthy runs): μ + k·σ (μ ± k·σ for two-sided indicators)
with σ the small-sample-corrected, floored spread of :func:`geardyn.diagnosis.baseline.
thresholds` (one value per reference record: its median over blocks). k follows from a
false-alarm probability P over the m usable indicators of a record, per-test level
α = 1 − (1 − P)^(1/m) (Šidák 1967), k = Φ⁻¹(1 − α): the warning level at ``p_warning``
(default 0.1), the alarm level at ``p_alarm`` ([diagnosis] false_alarm_probability, default
0.01): a healthy record crosses some warning level with probability ``p_warning`` and some
alarm level with probability ``p_alarm``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from geardyn.diagnosis.baseline import KEYS, ThresholdRule, thresholds
from geardyn.errors import InputError


@dataclass
class Levels:
    """``table``: KEYS, ``direction``, ``n``, ``mean``, ``sigma``, ``warning``, ``alarm`` (upper),
    ``warning_low``, ``alarm_low`` (two-sided); the factors and probabilities behind them."""

    table: pd.DataFrame
    k_warning: float
    k_alarm: float
    p_warning: float
    p_alarm: float
    tests: int
    source: str


def trend_levels(reference: list[pd.DataFrame], p_warning: float = 0.1,
                 p_alarm: float = 0.01, sigma_floor: float = 0.05,
                 source: str = "") -> Levels:
    """Levels from reference tables (one per healthy record; module docstring)."""
    from scipy.stats import norm

    from geardyn.diagnosis.localise import sidak_alpha

    if not 0 < p_alarm < p_warning < 1:
        raise InputError(f"levels: need 0 < alarm probability ({p_alarm:g}) < warning "
                         f"probability ({p_warning:g}) < 1")
    if len(reference) < 2:
        raise InputError(f"levels: {len(reference)} healthy reference record(s); at least 2 "
                         "are needed for a spread (--healthy)")
    first = thresholds(reference, ThresholdRule(sigma_floor=sigma_floor))
    m = max(int(first["usable"].sum()), 1)
    k_w = float(norm.isf(sidak_alpha(p_warning, m)))
    k_a = float(norm.isf(sidak_alpha(p_alarm, m)))
    tw = thresholds(reference, ThresholdRule(k=k_w, sigma_floor=sigma_floor))
    ta = thresholds(reference, ThresholdRule(k=k_a, sigma_floor=sigma_floor))
    t = tw[[*KEYS, "direction", "scale", "n", "mean", "sigma", "usable"]].copy()
    t["warning"], t["warning_low"] = tw["upper"].to_numpy(), tw["lower"].to_numpy()
    t["alarm"], t["alarm_low"] = ta["upper"].to_numpy(), ta["lower"].to_numpy()
    t["sigma_alarm"] = ta["sigma"].to_numpy()
    t = t[t["usable"]].drop(columns="usable").reset_index(drop=True)
    return Levels(t, k_w, k_a, p_warning, p_alarm, m, source)


def judge_records(history: pd.DataFrame, levels: Levels) -> pd.DataFrame:
    """Per record and row: the level reached (``ok``/``warning``/``alarm``) and the
    standardised deviation ``z`` = (value − μ)/σ (σ of the alarm level; on the scale of the
    level: (log value − log μ)/σ for log-scale rows, μ their geometric mean)."""
    h = history.merge(levels.table, on=KEYS, how="inner")
    v = h["value"].to_numpy(float)
    two = (h["direction"] == "two-sided").to_numpy()
    over_a = (v > h["alarm"].to_numpy()) | (two & (v < h["alarm_low"].to_numpy()))
    over_w = (v > h["warning"].to_numpy()) | (two & (v < h["warning_low"].to_numpy()))
    h["state"] = np.where(over_a, "alarm", np.where(over_w, "warning", "ok"))
    mean = h["mean"].to_numpy(float)
    log = (h["scale"] == "log").to_numpy() & (v > 0) & (mean > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        dev = np.where(log, np.log(np.where(log, v, 1.0) / np.where(log, mean, 1.0)), v - mean)
    h["z"] = dev / h["sigma_alarm"].to_numpy()
    return h


def component_states(judged: pd.DataFrame) -> pd.DataFrame:
    """Per record and component: the worst state, the indicator with the largest |z|."""
    order = {"ok": 0, "warning": 1, "alarm": 2}
    j = judged.assign(rank=judged["state"].map(order), absz=judged["z"].abs())
    j = j.sort_values(["rank", "absz"], ascending=False, kind="stable")
    worst = j.groupby(["key", "component"], sort=False).head(1)
    cols = ["key", "file", "timestamp", "component", "kind", "state", "indicator", "value", "z"]
    return worst[cols].sort_values(["timestamp", "component"], kind="stable").reset_index(
        drop=True)


def first_crossings(states: pd.DataFrame) -> pd.DataFrame:
    """Per component and level, the first record (in time) at or above it."""
    rows = []
    for comp, g in states.groupby("component", sort=False):
        g = g.sort_values("timestamp", kind="stable")
        for level, ok in (("warning", g["state"].isin(["warning", "alarm"])),
                          ("alarm", g["state"] == "alarm")):
            if ok.any():
                r = g[ok].iloc[0]
                rows.append({"component": comp, "level": level, "file": r["file"],
                             "timestamp": r["timestamp"], "indicator": r["indicator"],
                             "z": r["z"]})
    return pd.DataFrame(rows, columns=["component", "level", "file", "timestamp", "indicator",
                                       "z"])
