"""Thresholds from baseline records grouped by their dynamic run (issue 18: members measured on
one simulated machine share its dynamics; the prediction bound must count machines, not
measurements)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy.stats import t as student

from geardyn.diagnosis.baseline import ThresholdRule, prediction_spread, thresholds
from geardyn.diagnosis.isolation import evidence_from_null


def test_one_record_per_run_is_the_plain_prediction_bound() -> None:
    # Hahn & Meeker 1991 ch. 4: centre mean, sd s·√(1 + 1/n), n − 1 degrees of freedom
    x = np.array([0.3, -1.2, 0.8, 2.0, 0.1])
    for runs in (None, ["a", "b", "c", "d", "e"]):
        c, sd, df = prediction_spread(x, runs)
        assert c == pytest.approx(x.mean(), rel=1e-14)
        assert sd == pytest.approx(x.std(ddof=1) * math.sqrt(1.2), rel=1e-14)
        assert df == 4


def test_balanced_runs_closed_form() -> None:
    # R = 3 runs × M = 2: V = (1 + 1/R)·S_b² + (1 − 1/M)·MS_w (Searle et al. 1992 ch. 3,
    # variance of y_new − ȳ), Satterthwaite 1946 degrees of freedom
    x = np.array([1.0, 1.4, 3.0, 2.6, -0.5, 0.1])
    runs = [0, 0, 1, 1, 2, 2]
    means = np.array([1.2, 2.8, -0.2])
    s_b2 = means.var(ddof=1)
    ms_w = (0.2**2 * 2 + 0.2**2 * 2 + 0.3**2 * 2) / 3
    a, b = (4 / 3) * s_b2, 0.5 * ms_w
    c, sd, df = prediction_spread(x, runs)
    assert c == pytest.approx(means.mean(), rel=1e-14)
    assert sd == pytest.approx(math.sqrt(a + b), rel=1e-12)
    assert df == pytest.approx((a + b) ** 2 / (a * a / 2 + b * b / 3), rel=1e-12)


@pytest.mark.parametrize(("sigma_run", "sigma_meas"), [(1.0, 0.3), (0.3, 1.0)])
def test_bound_keeps_its_false_alarm_probability(sigma_run: float, sigma_meas: float) -> None:
    """Monte Carlo: 6 runs × 2 measurements, a new record from a new run exceeds the bound at
    α = 0.05 with probability ≈ α (Satterthwaite is approximate: a binomial 4-SE band plus 1 %
    absolute); treating the 12 records as independent exceeds it clearly more often when the
    run effect dominates (the defect this guards against)."""
    rng = np.random.default_rng(7)
    alpha, n_mc, n_runs, m = 0.05, 6000, 6, 2
    runs = np.repeat(np.arange(n_runs), m)
    hit_runs = hit_iid = 0
    for _ in range(n_mc):
        x = (rng.normal(0, sigma_run, n_runs)[:, None]
             + rng.normal(0, sigma_meas, (n_runs, m))).ravel()
        new = rng.normal(0, sigma_run) + rng.normal(0, sigma_meas)
        c, sd, df = prediction_spread(x, runs)
        hit_runs += new > c + student.isf(alpha, df) * sd
        c, sd, df = prediction_spread(x, None)
        hit_iid += new > c + student.isf(alpha, df) * sd
    se = math.sqrt(alpha * (1 - alpha) / n_mc)
    assert abs(hit_runs / n_mc - alpha) < 4 * se + 0.01
    if sigma_run > sigma_meas:
        assert hit_iid / n_mc > alpha + 4 * se


def _table(values: list[float]) -> pd.DataFrame:
    return pd.DataFrame({"component": "sun", "kind": "sun", "indicator": "FM4",
                         "value": values, "block": range(len(values)), "channel": "acc"})


def test_thresholds_count_runs_not_measurements() -> None:
    # two measurements per run that agree closely: 6 runs carry the spread, not 12 records
    rng = np.random.default_rng(3)
    level = np.exp(rng.normal(1.0, 0.2, 6))
    tables = [_table([v * (1 + 0.01 * rng.standard_normal())]) for v in level for _ in (0, 1)]
    runs = [r for r in range(6) for _ in (0, 1)]
    rule = ThresholdRule(k=3.7, sigma_floor=0.0)
    grouped = thresholds(tables, rule, runs).iloc[0]
    iid = thresholds(tables, rule).iloc[0]
    assert grouped["upper"] > iid["upper"]
    with pytest.raises(Exception, match="runs: one run label per baseline table"):
        thresholds(tables, rule, runs[:-1])


def test_evidence_null_grouped_by_runs_is_wider() -> None:
    rng = np.random.default_rng(5)
    null = [float(np.exp(v + 0.01 * rng.standard_normal()))
            for v in rng.normal(0.0, 0.3, 6) for _ in (0, 1)]
    runs = [r for r in range(6) for _ in (0, 1)]
    a = evidence_from_null("sun", "cSDR", 2.0, null, 1e-3, runs=runs)
    b = evidence_from_null("sun", "cSDR", 2.0, null, 1e-3)
    assert a.threshold > b.threshold
    assert a.df < b.df == 11
    assert a.bound(1e-3) == pytest.approx(a.threshold, rel=1e-12)


def test_two_null_values_at_a_small_level_give_an_infinite_threshold() -> None:
    # t_1 at α = 1.3e-4 times a log spread of 0.37 is beyond exp's range: no usable threshold,
    # never an OverflowError (null of the input-ball BPFO band energy in an FE record)
    ev = evidence_from_null("input ball", "BPFO band energy", 0.3, [0.154, 0.258], 1.3e-4)
    assert ev.threshold == math.inf
    assert not ev.passed
    assert ev.bound(1e-9) == math.inf
