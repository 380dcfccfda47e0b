"""Alarm thresholds from a healthy baseline.

The baseline is one or more indicator tables in the long format of
:func:`geardyn.diagnosis.features.features_from_result` (columns ``component, kind, indicator,
value, block, channel``), one per healthy record (a baseline-ensemble member, a simulation seed
or a measured healthy record).

**Samples.** A record is judged by the median of its blocks; the null sample of an indicator
is the same statistic of every baseline record (``replicate = "record"``, the default: the
unit of replication is the machine-and-measurement, not the block — blocks of one record share
its machine and are not independent). Keys with fewer than 2 baseline records fall back to
pooling every block of every record (``replicate = "block"``).

**Scale.** Condition indicators of the higher-is-worse kind are positive (kurtosis, RMS and
energy ratios) and their spread over a fleet is multiplicative and right-skewed: with
``log_scale`` (default) a key whose samples are all > 0 is thresholded on the logarithm of
the values (a log-normal model; Limpert, Stahel & Abbt 2001) and the threshold is brought back
to the indicator's unit; other keys (a value ≤ 0, two-sided indicators) on the values.

Rule (:class:`ThresholdRule`): with μ and s the mean and sample standard deviation (ddof = 1)
of the n samples (values or logarithms),

* small-sample correction: a healthy record is a new draw, not one of the n, and s is itself
  uncertain, so s is scaled by c_n = t_{n−1}(Φ(k))·√(1 + 1/n) / k — the one-sided Gaussian
  prediction bound μ + t·s·√(1 + 1/n) that a new healthy value exceeds with the probability
  1 − Φ(k) (0.13 % for k = 3) that μ + kσ has for a known σ (prediction interval for one
  future observation of a normal sample: Hahn & Meeker, *Statistical Intervals*, 1991, ch. 4).
  c_n = 7.4 for n = 3, 2.0 for n = 6, 1.3 for n = 12, → 1 for large n; a single sample
  (n = 1) has no spread estimate and keeps only the floor below;
* σ = max(c_n·s, floor) with the floor a fraction ``f`` (``sigma_floor``, default 5 %) of the
  mean (log scale: log(1 + f)), so that a deterministic baseline (simulated, nearly identical
  seeds) does not alarm on numerical noise;
* upper threshold μ + k·σ (log scale: exp(μ + k·σ)) for indicators where higher is worse;
* for two-sided indicators (:data:`TWO_SIDED`, e.g. skewness, whose sign flips with the sense
  of an impact) also a lower threshold μ − k·σ.

Every indicator is taken as higher-is-worse except those in :data:`TWO_SIDED`; indicators in
:data:`NOT_JUDGED` (operating-point values such as speeds) are not thresholded. An indicator
whose σ is 0 (no spread and μ = 0) or whose values are not finite has no usable threshold.
The ``mean`` and ``std`` columns are those of the samples on their scale (``scale``: log rows
give the geometric mean and the standard deviation of the logarithm).
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
    replicate: str = "record"
    """``"record"``: one sample per baseline record (median of its blocks); ``"block"``: every
    block pooled (module docstring)."""
    log_scale: bool = True
    """Threshold positive higher-is-worse indicators on the logarithm of their values."""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.k) and self.k > 0):
            raise InputError(f"k: threshold factor must be a finite number > 0, got {self.k!r}")
        if not (math.isfinite(self.sigma_floor) and 0 <= self.sigma_floor < 1):
            raise InputError(
                f"sigma_floor: fraction of |mean| must be in [0, 1), got {self.sigma_floor!r}"
            )
        if self.replicate not in ("record", "block"):
            raise InputError(f"replicate: 'record' or 'block', got {self.replicate!r}")

    def describe(self) -> str:
        """One line stating the rule (for the report and verdict.json)."""
        c = "c_n·std" if self.small_sample else "std"
        cn = (f"; c_n = t_(n−1)(Φ({self.k:g}))·√(1 + 1/n)/{self.k:g} (one-sided prediction "
              "bound for a new healthy record from n baseline samples)"
              if self.small_sample else "")
        unit = ("one sample per baseline record (median of its blocks)"
                if self.replicate == "record" else "the pooled baseline blocks")
        scale = ("; positive higher-is-worse indicators on the log scale (threshold = "
                 f"exp(mean + {self.k:g}·σ) of the log values, floor log(1 + "
                 f"{self.sigma_floor:g}))" if self.log_scale else "")
        return (
            f"threshold = mean + {self.k:g}·σ over {unit}, "
            f"σ = max({c}, {self.sigma_floor:g}·|mean|){cn}{scale}; two-sided (mean ± "
            f"{self.k:g}·σ) for {', '.join(sorted(TWO_SIDED))}"
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
    rows = rows[np.isfinite(rows["value"].to_numpy(float))]
    if rule.replicate == "record":
        per = rows.groupby([*KEYS, "record"], sort=False)["value"].median().reset_index()
        records = per.groupby(KEYS, sort=False)["record"].transform("size")
        blocks = rows.merge(per.loc[records < 2, KEYS].drop_duplicates(), on=KEYS)
        rows = pd.concat([per.loc[records >= 2], blocks], ignore_index=True)
    out = []
    for key, g in rows.groupby(KEYS, sort=False):
        out.append(_row(dict(zip(KEYS, key, strict=True)), g["value"].to_numpy(float), rule))
    if not out:
        raise InputError("baseline: no finite indicator value in the baseline tables")
    stats = pd.DataFrame(out)
    cols = [*KEYS, "direction", "scale", "n", "mean", "std", "sigma", "lower", "upper",
            "usable"]
    return stats[cols]


def _row(key: dict[str, str], v: np.ndarray, rule: ThresholdRule) -> dict[str, object]:
    """Threshold row of one key from its samples ``v`` (module docstring)."""
    dirn = direction(str(key["indicator"]))
    n = int(v.size)
    log = rule.log_scale and dirn == "upper" and n > 0 and bool(np.all(v > 0))
    x = np.log(v) if log else v
    mean = float(x.mean()) if n else math.nan
    std = float(x.std(ddof=1)) if n > 1 else (0.0 if n else math.nan)
    spread = float(rule.spread_factor(np.array([n]))[0]) * std
    floor = math.log1p(rule.sigma_floor) if log else rule.sigma_floor * abs(mean)
    sigma = max(spread, floor)
    upper = mean + rule.k * sigma
    lower = mean - rule.k * sigma if dirn == "two-sided" else math.nan
    if log:  # a spread too wide for exp's range leaves no usable threshold
        mean = math.exp(mean)
        upper = math.exp(upper) if upper < 700.0 else math.inf
    usable = n > 0 and math.isfinite(upper) and sigma > 0
    return {**key, "direction": dirn, "scale": "log" if log else "linear", "n": n,
            "mean": mean, "std": std, "sigma": sigma, "lower": lower, "upper": upper,
            "usable": usable}
