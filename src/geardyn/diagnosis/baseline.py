"""Alarm thresholds from a healthy baseline.

The baseline is one or more indicator tables in the long format of
:func:`geardyn.diagnosis.features.features_from_result` (columns ``component, kind, indicator,
value, block, channel``), e.g. one per simulation seed or measured healthy record. All their
rows are pooled per ``(component, kind, indicator, channel)``: every block of whole revolutions
of every baseline record is one sample.

Rule (:class:`ThresholdRule`): with μ and s the mean and sample standard deviation (ddof = 1)
of the n pooled values,

* small-sample correction: a healthy record is a new draw, not one of the n, and s is itself
  uncertain, so s is scaled by c_n = t_{n−1}(Φ(k))·√(1 + 1/n) / k — the one-sided Gaussian
  prediction bound μ + t·s·√(1 + 1/n) that a new healthy value exceeds with the probability
  1 − Φ(k) (0.13 % for k = 3) that μ + kσ has for a known σ (prediction interval for one
  future observation of a normal sample: Hahn & Meeker, *Statistical Intervals*, 1991, ch. 4).
  c_n = 7.4 for n = 3, 2.0 for n = 6, 1.3 for n = 12, → 1 for large n; a single sample
  (n = 1) has no spread estimate and keeps only the floor below;
* σ = max(c_n·s, f·|μ|) — the spread is floored at a fraction ``f`` (``sigma_floor``, default
  5 %) of the mean, so that a deterministic baseline (simulated, nearly identical seeds) does
  not alarm on numerical noise;
* upper threshold μ + k·σ (k = ``k``, default 3) for indicators where higher is worse;
* for two-sided indicators (:data:`TWO_SIDED`, e.g. skewness, whose sign flips with the sense
  of an impact) also a lower threshold μ − k·σ.

Every indicator is taken as higher-is-worse except those in :data:`TWO_SIDED`; indicators in
:data:`NOT_JUDGED` (operating-point values such as speeds) are not thresholded. An indicator
whose σ is 0 (no spread and μ = 0) or whose values are not finite has no usable threshold.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from geardyn.errors import InputError

#: Columns of an indicator table (long format).
COLUMNS = ("component", "kind", "indicator", "value", "block", "channel")
#: Keys of a threshold: one threshold per component, indicator and channel.
KEYS = ["component", "kind", "indicator", "channel"]
#: Indicators judged on both sides (deviation from the healthy mean in either direction).
TWO_SIDED = frozenset({"skewness"})
#: Values reported in the tables but never thresholded (operating point, not condition).
NOT_JUDGED = frozenset({"speed_rpm", "speed_hz", "revolutions", "samples_per_rev"})


@dataclass(frozen=True)
class ThresholdRule:
    """Threshold = μ + k·σ with σ = max(c_n·s, ``sigma_floor``·|μ|), c_n the small-sample
    factor (``small_sample=False``: c_n = 1) (module docstring)."""

    k: float = 3.0
    sigma_floor: float = 0.05
    small_sample: bool = True

    def __post_init__(self) -> None:
        if not (math.isfinite(self.k) and self.k > 0):
            raise InputError(f"k: threshold factor must be a finite number > 0, got {self.k!r}")
        if not (math.isfinite(self.sigma_floor) and 0 <= self.sigma_floor < 1):
            raise InputError(
                f"sigma_floor: fraction of |mean| must be in [0, 1), got {self.sigma_floor!r}"
            )

    def describe(self) -> str:
        """One line stating the rule (for the report and verdict.json)."""
        c = "c_n·std" if self.small_sample else "std"
        cn = (f"; c_n = t_(n−1)(Φ({self.k:g}))·√(1 + 1/n)/{self.k:g} (one-sided prediction "
              "bound for a new healthy record from n baseline samples)"
              if self.small_sample else "")
        return (
            f"threshold = mean + {self.k:g}·σ over the pooled baseline blocks, "
            f"σ = max({c}, {self.sigma_floor:g}·|mean|){cn}; two-sided (mean ± {self.k:g}·σ) "
            f"for {', '.join(sorted(TWO_SIDED))}"
        )

    def spread_factor(self, n: np.ndarray) -> np.ndarray:
        """c_n for sample counts ``n`` (1 where n < 2: no spread estimate, or no correction)."""
        n = np.asarray(n, dtype=float)
        if not self.small_sample:
            return np.ones_like(n)
        from scipy.stats import norm
        from scipy.stats import t as student

        df = np.maximum(n - 1, 1)
        c = student.ppf(norm.cdf(self.k), df) * np.sqrt(1 + 1 / np.maximum(n, 1)) / self.k
        return np.where(n >= 2, c, 1.0)


def direction(indicator: str) -> str:
    """``'upper'`` (higher is worse), ``'two-sided'`` or ``'none'`` (not judged)."""
    if indicator in NOT_JUDGED:
        return "none"
    return "two-sided" if indicator in TWO_SIDED else "upper"


def check_table(table: pd.DataFrame, what: str = "indicator table") -> pd.DataFrame:
    """The table with its columns checked (InputError naming the missing ones)."""
    if not isinstance(table, pd.DataFrame):
        raise InputError(f"{what}: expected a pandas DataFrame, got {type(table).__name__}")
    missing = [c for c in COLUMNS if c not in table.columns]
    if missing:
        raise InputError(
            f"{what}: missing column(s) {', '.join(missing)}; an indicator table has the "
            f"columns {', '.join(COLUMNS)}"
        )
    out = table.loc[:, list(COLUMNS)].copy()
    out["value"] = pd.to_numeric(out["value"], errors="coerce").astype(float)
    out["channel"] = out["channel"].fillna("").astype(str)
    return out


def pool(tables: pd.DataFrame | Iterable[pd.DataFrame]) -> pd.DataFrame:
    """One long table from several baseline tables (seeds / records); a ``record`` column holds
    the index of the table each row came from."""
    if isinstance(tables, pd.DataFrame):
        tables = [tables]
    parts = [check_table(t, f"baseline table {i}").assign(record=i) for i, t in enumerate(tables)]
    if not parts:
        raise InputError("baseline: no indicator table given (at least one healthy record)")
    return pd.concat(parts, ignore_index=True)


def _stats(values: pd.Series) -> pd.Series:
    v = values.to_numpy(dtype=float)
    v = v[np.isfinite(v)]
    n = v.size
    mean = float(v.mean()) if n else math.nan
    std = float(v.std(ddof=1)) if n > 1 else (0.0 if n else math.nan)
    return pd.Series({"n": n, "mean": mean, "std": std})


def thresholds(
    baseline: pd.DataFrame | Iterable[pd.DataFrame], rule: ThresholdRule | None = None
) -> pd.DataFrame:
    """Thresholds per ``(component, kind, indicator, channel)`` from baseline tables.

    Returns a DataFrame with the key columns and ``direction, n, mean, std, sigma, lower,
    upper, usable``: ``n`` pooled finite samples, ``std`` their sample standard deviation,
    ``sigma`` the corrected and floored spread, ``upper`` = mean + k·sigma, ``lower`` =
    mean − k·sigma for two-sided indicators (NaN otherwise). Indicators in
    :data:`NOT_JUDGED` are left out.
    """
    rule = rule or ThresholdRule()
    rows = pool(baseline)
    rows = rows[[direction(str(i)) != "none" for i in rows["indicator"]]]
    if rows.empty:
        raise InputError("baseline: no thresholdable indicator in the baseline tables")
    stats = rows.groupby(KEYS, sort=False)["value"].apply(_stats).unstack().reset_index()
    stats["n"] = stats["n"].astype(int)
    stats["direction"] = [direction(str(i)) for i in stats["indicator"]]
    spread = rule.spread_factor(stats["n"].to_numpy()) * stats["std"]
    stats["sigma"] = np.maximum(spread, rule.sigma_floor * stats["mean"].abs())
    stats["upper"] = stats["mean"] + rule.k * stats["sigma"]
    two = stats["direction"] == "two-sided"
    stats["lower"] = np.where(two, stats["mean"] - rule.k * stats["sigma"], np.nan)
    stats["usable"] = (stats["n"] > 0) & np.isfinite(stats["upper"]) & (stats["sigma"] > 0)
    cols = [*KEYS, "direction", "n", "mean", "std", "sigma", "lower", "upper", "usable"]
    return stats[cols]
