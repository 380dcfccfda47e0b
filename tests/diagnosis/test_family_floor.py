"""Family floor of the thresholds (issue 18, false alarms): a log-scale spread is raised to the
median spread of the same indicator over the machine's other components, never lowered
(geardyn.diagnosis.baseline.family_floor, geardyn.diagnosis.isolation.family_floor)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy.stats import t as student

from geardyn.diagnosis.baseline import ThresholdRule, thresholds
from geardyn.diagnosis.isolation import evidence_from_null, family_floor


def _tables(values: dict[tuple[str, str], list[float]]) -> list[pd.DataFrame]:
    """One indicator table per baseline record from (component, indicator) → values."""
    n = len(next(iter(values.values())))
    return [pd.DataFrame([{"component": c, "kind": "wheel", "indicator": i, "value": v[r],
                           "block": 0, "channel": "acc"} for (c, i), v in values.items()])
            for r in range(n)]


SPREADS = {("sun", "FM4"): 0.02, ("planet", "FM4"): 0.20, ("ring", "FM4"): 0.30,
           ("carrier", "FM4"): 0.25, ("sun", "ER"): 0.01, ("ring", "ER"): 0.01}


def _baseline(seed: int = 3) -> dict[tuple[str, str], list[float]]:
    rng = np.random.default_rng(seed)
    z = rng.standard_normal(6)
    z = (z - z.mean()) / z.std(ddof=1)  # sample std of every key's logs = its spread
    return {k: list(3.0 * np.exp(s * z)) for k, s in SPREADS.items()}


def test_a_clustered_key_gets_its_family_median_spread() -> None:
    k = 4.0
    on = thresholds(_tables(_baseline()), ThresholdRule(k=k, small_sample=False))
    off = thresholds(_tables(_baseline()), ThresholdRule(k=k, small_sample=False,
                                                         family_floor=False))
    on, off = (t.set_index(["component", "indicator"]) for t in (on, off))
    # FM4 family: spreads 0.02, 0.20, 0.25, 0.30 (sample std of the logs, small_sample off)
    median = float(np.median([0.02, 0.20, 0.25, 0.30]))
    assert off.loc[("sun", "FM4"), "sigma"] == pytest.approx(max(0.02, math.log1p(0.05)),
                                                             rel=1e-9)
    assert on.loc[("sun", "FM4"), "sigma"] == pytest.approx(median, rel=1e-9)
    assert on.loc[("sun", "FM4"), "upper"] == pytest.approx(
        on.loc[("sun", "FM4"), "mean"] * math.exp(k * median), rel=1e-9)
    for key in [("planet", "FM4"), ("ring", "FM4"), ("carrier", "FM4")]:
        if off.loc[key, "sigma"] >= median:  # at or above the median: untouched
            assert on.loc[key, "sigma"] == off.loc[key, "sigma"]
            assert on.loc[key, "upper"] == off.loc[key, "upper"]
    # another indicator is another family: ER keeps its own (floored) spread
    assert on.loc[("sun", "ER"), "sigma"] == off.loc[("sun", "ER"), "sigma"]
    # never lowered, anywhere
    assert (on["sigma"] >= off["sigma"] - 1e-15).all()
    assert (on["upper"] >= off["upper"] * (1 - 1e-15)).all()
    assert "family floor" in ThresholdRule().describe()
    # bearings are no family (each line's spread depends on the bearing's own geometry)
    tables = _tables(_baseline())
    for t in tables:
        t.loc[t["component"] == "sun", "kind"] = "bearing"
    b = thresholds(tables, ThresholdRule(k=k, small_sample=False)).set_index(
        ["component", "indicator"])
    assert b.loc[("sun", "FM4"), "sigma"] == off.loc[("sun", "FM4"), "sigma"]
    assert "family floor" not in ThresholdRule(family_floor=False).describe()


def test_evidence_family_floor_recomputes_the_bound() -> None:
    rng = np.random.default_rng(5)
    alpha = 1e-3
    evs = [evidence_from_null(f"domain {i}", "cSDR", 0.02,
                              list(0.01 * np.exp(s * rng.standard_normal(8))), alpha)
           for i, s in enumerate((0.05, 0.4, 0.6, 0.5))]
    out = family_floor(evs, alpha)
    floor = float(np.median([e.scale for e in evs]))
    for e, f in zip(evs, out, strict=True):
        assert f.scale == pytest.approx(max(e.scale, floor), rel=1e-12)
        mu = math.log(e.mean)
        assert f.threshold == pytest.approx(
            math.exp(mu + student.isf(alpha, e.df) * f.scale), rel=1e-12)
        assert f.z == pytest.approx((math.log(e.value) - mu) / f.scale, rel=1e-12)
        assert f.p == pytest.approx(student.sf(f.z, e.df), rel=1e-12)
        assert f.threshold >= e.threshold * (1 - 1e-15)
    assert out[0].scale == pytest.approx(floor) and out[0].threshold > evs[0].threshold
    assert family_floor(evs[:2], alpha) == evs[:2]  # fewer than 3 tests: nothing to pool


def test_the_floor_keeps_a_heavy_tailed_population_near_its_false_alarm_probability() -> None:
    """Why (docs/diagnosis.md, false alarms): components of one machine share heavy-tailed
    drivers. Monte Carlo, log indicators of 5 components from one Student t₃ population (the
    same law for every key), 6-run baselines, α = 1 %: bounds from each key's own 6 runs
    exceed α on new draws when the runs happen to cluster; the family floor brings the rate
    down, and never above the per-key rate."""
    rng = np.random.default_rng(2026)
    alpha, trials, keys = 0.01, 4000, 5
    k = float(student.isf(alpha, 5)) * math.sqrt(1 + 1 / 6)
    own = pooled = 0
    for _ in range(trials):
        x = 0.3 * rng.standard_t(3, size=(keys, 7))
        base, new = x[:, :6], x[:, 6]
        s = base.std(axis=1, ddof=1)
        s_f = np.maximum(s, np.median(s))
        mu = base.mean(axis=1)
        own += int(np.sum(new > mu + k * s))
        pooled += int(np.sum(new > mu + k * s_f))
    own_rate, pooled_rate = own / (trials * keys), pooled / (trials * keys)
    assert pooled_rate < own_rate
    assert pooled_rate < 1.5 * alpha < own_rate  # regression guard of this Monte Carlo


def test_the_option_is_in_diagnosis_and_checked() -> None:
    from pydantic import ValidationError

    from geardyn.config.diagnosis import DiagnosisSpec

    assert DiagnosisSpec().family_floor is True
    assert DiagnosisSpec(family_floor=False).family_floor is False
    with pytest.raises(ValidationError, match="family_floor"):
        DiagnosisSpec(family_floor="sometimes")
