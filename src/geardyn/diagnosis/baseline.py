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
* **runs**: baseline records measured on one dynamic run (``measurements_per_run`` sensor
  variants of one simulated machine) share its dynamics, so they are not n independent
  machines. Given the run of each record (``runs``), the samples are taken as a one-way
  random-effects model (runs, and records within runs; Searle, Casella & McCulloch 1992,
  ch. 3): with R runs, group means ȳ_r, their mean ȳ, S_b² their variance, MS_w the pooled
  within-run variance and h the mean of 1/m_r over the runs' record counts m_r, the variance
  of a new record minus ȳ is V = (1 + 1/R)·S_b² + (1 − h)·MS_w (not below (1 + h/R)·MS_w, the
  value without a run effect) with Satterthwaite's (1946) degrees of freedom
  ν = V² / ((1 + 1/R)²S_b⁴/(R − 1) + (1 − h)²MS_w²/(N − R)); the bound is
  ȳ + t_ν·√V. One record per run gives back the bound above (V = (1 + 1/n)·s², ν = n − 1);
  without ``runs`` every record is its own run;
* σ = max(c_n·s, floor) with the floor a fraction ``f`` (``sigma_floor``, default 5 %) of the
  mean (log scale: log(1 + f)), so that a deterministic baseline (simulated, nearly identical
  seeds) does not alarm on numerical noise;
* **family floor** (``family_floor``, default on): on the log scale, σ is raised to the median
  σ of the same indicator over every key of the table (the indicator's *family*: FM4 of the
  sun, the planets and the ring; bearings excepted, whose line spreads depend on each
  bearing's own geometry). A spread estimated from
  a few dynamic runs is itself uncertain, and the components of one machine see the same
  drivers (manufacturing errors, clearances, operating point): a key whose runs happen to
  cluster must not get a bound narrower than its family's typical one. The pooling borrows
  strength across tests as moderated variances do (Smyth 2004), but one-sided: a σ is never
  lowered, so every test keeps at least the bound above (docs/diagnosis.md, "False alarms");
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
from collections.abc import Iterable, Sequence
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
    family_floor: bool = True
    """Raise each log-scale σ to the median σ of its indicator over the table's keys (module
    docstring)."""

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
        fam = ("; on the log scale σ is at least the median σ of the same indicator over "
               "the other components (family floor, borrowing strength across tests as "
               "Smyth 2004; never lowered)" if self.family_floor else "")
        return (
            f"threshold = mean + {self.k:g}·σ over {unit}, "
            f"σ = max({c}, {self.sigma_floor:g}·|mean|){cn}{scale}{fam}; two-sided (mean ± "
            f"{self.k:g}·σ) for {', '.join(sorted(TWO_SIDED))}"
        )

    def prediction_sigma(self, x: np.ndarray, runs: np.ndarray | None = None) -> float:
        """σ of the rule for samples ``x`` (before the floor): c_n·s for independent samples,
        t_ν(Φ(k))·√V/k for records grouped by ``runs`` (:func:`prediction_spread`)."""
        x = np.asarray(x, float)
        if x.size < 2:
            return 0.0
        if not self.small_sample:
            return float(x.std(ddof=1))
        from scipy.stats import norm
        from scipy.stats import t as student

        _, sd, df = prediction_spread(x, runs)
        return float(student.ppf(norm.cdf(self.k), df)) * sd / self.k

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


def prediction_spread(x: np.ndarray, runs: Sequence[object] | np.ndarray | None = None
                      ) -> tuple[float, float, float]:
    """Centre, standard deviation and degrees of freedom of the prediction of one new record
    from samples ``x`` grouped by ``runs`` (module docstring, "runs"): ``(ȳ, √V, ν)``. Without
    runs, or with one record per run, ``(mean, s·√(1 + 1/n), n − 1)`` (Hahn & Meeker 1991,
    ch. 4). A single run carries no run-to-run spread: its records are taken as independent.
    """
    x = np.asarray(x, float)
    n = x.size
    if n < 2:
        return (float(x.mean()) if n else math.nan), math.nan, math.nan
    labels = (np.arange(n) if runs is None
              else np.unique(np.asarray(runs, dtype=object).astype(str),
                             return_inverse=True)[1])
    n_runs = int(labels.max()) + 1
    if n_runs == n or n_runs < 2:
        return float(x.mean()), float(x.std(ddof=1) * math.sqrt(1.0 + 1.0 / n)), n - 1.0
    m = np.bincount(labels).astype(float)
    means = np.bincount(labels, weights=x) / m
    centre = float(means.mean())
    s_b2 = float(means.var(ddof=1))
    ms_w = float(np.sum((x - means[labels]) ** 2) / (n - n_runs))
    h = float(np.mean(1.0 / m))
    a = (1.0 + 1.0 / n_runs) * s_b2
    b = (1.0 - h) * ms_w
    v = max(a + b, (1.0 + h / n_runs) * ms_w)
    den = a * a / (n_runs - 1) + b * b / (n - n_runs)
    df = v * v / den if den > 0 else n - 1.0
    return centre, math.sqrt(v), float(min(max(df, 1.0), n - 1.0))


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
    baseline: pd.DataFrame | Iterable[pd.DataFrame], rule: ThresholdRule | None = None,
    runs: Sequence[object] | None = None,
) -> pd.DataFrame:
    """Thresholds per ``(component, kind, indicator, channel)`` from baseline tables.

    Returns a DataFrame with the key columns and ``direction, n, mean, std, sigma, lower,
    upper, usable``: ``n`` pooled finite samples, ``std`` their sample standard deviation,
    ``sigma`` the corrected and floored spread, ``upper`` = mean + k·sigma, ``lower`` =
    mean − k·sigma for two-sided indicators (NaN otherwise). Indicators in
    :data:`NOT_JUDGED` are left out. ``runs``: the dynamic run of each baseline table (records
    of one run share its dynamics; module docstring), None: every table its own run.
    """
    rule = rule or ThresholdRule()
    rows = pool(baseline)
    n_tables = int(rows["record"].max()) + 1
    if runs is not None and len(runs) != n_tables:
        raise InputError(f"runs: one run label per baseline table ({n_tables}), got {len(runs)}")
    run_of = (np.arange(n_tables).astype(str) if runs is None or None in list(runs)
              else np.asarray([str(r) for r in runs]))
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
        grouped = run_of[g["record"].to_numpy(int)]
        if len(set(zip(grouped, g["record"], strict=True))) != len(g):  # block rows
            grouped = None
        out.append(_row(dict(zip(KEYS, key, strict=True)), g["value"].to_numpy(float), rule,
                        grouped))
    if not out:
        raise InputError("baseline: no finite indicator value in the baseline tables")
    stats = pd.DataFrame(out)
    if rule.family_floor:
        stats = family_floor(stats, rule.k)
    cols = [*KEYS, "direction", "scale", "n", "mean", "std", "sigma", "lower", "upper",
            "usable"]
    return stats[cols]


def family_floor(stats: pd.DataFrame, k: float) -> pd.DataFrame:
    """Threshold rows with every usable log-scale σ raised to the median σ of its indicator
    over the table's usable log-scale keys (module docstring, "family floor"); the upper
    threshold follows (exp(log mean + k·σ)). Linear-scale rows and bearings are left as they
    are: a bearing line's spread depends on which deterministic lines its band meets, the
    bearing's own geometry, so bearings are no family."""
    out = stats.copy()
    sig = out["sigma"].to_numpy(float)
    ok = ((out["scale"] == "log") & out["usable"].astype(bool)
          & (out["kind"] != "bearing")).to_numpy() & np.isfinite(sig)
    if not ok.any():
        return out
    floor = out.loc[ok].groupby("indicator")["sigma"].transform("median")
    raise_ = floor.to_numpy(float) > sig[ok]
    idx = out.index[ok][raise_]
    if len(idx):
        new = floor.to_numpy(float)[raise_]
        mean = out.loc[idx, "mean"].to_numpy(float)
        arg = np.log(mean) + k * new
        out.loc[idx, "sigma"] = new
        out.loc[idx, "upper"] = np.where(arg < 700.0, np.exp(np.minimum(arg, 700.0)), np.inf)
    return out


def _row(key: dict[str, str], v: np.ndarray, rule: ThresholdRule,
         runs: np.ndarray | None = None) -> dict[str, object]:
    """Threshold row of one key from its samples ``v`` (of the runs ``runs``; module
    docstring)."""
    dirn = direction(str(key["indicator"]))
    n = int(v.size)
    log = rule.log_scale and dirn == "upper" and n > 0 and bool(np.all(v > 0))
    x = np.log(v) if log else v
    mean = prediction_spread(x, runs)[0] if n else math.nan
    std = float(x.std(ddof=1)) if n > 1 else (0.0 if n else math.nan)
    spread = rule.prediction_sigma(x, runs)
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
