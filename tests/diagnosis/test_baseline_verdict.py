"""Baseline thresholds and verdicts on synthetic indicator tables with known mean and spread,
and the fault bookkeeping of configs (healthy variant, fault list)."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

import geardyn
from geardyn.config.loader import parse_config
from geardyn.diagnosis.baseline import ThresholdRule, thresholds
from geardyn.diagnosis.faults import ConfiguredFault, fault_list, healthy_variant
from geardyn.diagnosis.verdict import judge, read_verdict, record_values
from geardyn.errors import InputError
from tests.conftest import EXAMPLES


def table(values: dict[tuple[str, str, str], list[float]], channel: str = "acc") -> pd.DataFrame:
    """Long indicator table: one row per (component, kind, indicator) and block."""
    rows = [
        {"component": c, "kind": k, "indicator": i, "value": v, "block": b, "channel": channel}
        for (c, k, i), vals in values.items()
        for b, v in enumerate(vals)
    ]
    return pd.DataFrame(rows)


def row(th: pd.DataFrame, component: str, indicator: str) -> pd.Series:
    return th[(th["component"] == component) & (th["indicator"] == indicator)].iloc[0]


def test_threshold_is_mean_plus_k_std_pooled_over_tables() -> None:
    # two seeds × 2 blocks: pooled 1, 3, 5, 7 → mean 4, sample std sqrt(20/3)
    a = table({("sun", "sun", "FM4"): [1.0, 3.0]})
    b = table({("sun", "sun", "FM4"): [5.0, 7.0]})
    th = thresholds([a, b], ThresholdRule(k=3.0, sigma_floor=0.05, small_sample=False,
                                          replicate="block", log_scale=False))
    r = row(th, "sun", "FM4")
    s = math.sqrt(20.0 / 3.0)
    assert r["n"] == 4
    assert r["mean"] == pytest.approx(4.0)
    assert r["std"] == pytest.approx(s)
    assert r["sigma"] == pytest.approx(s)  # 5 % of 4 = 0.2 < s: no floor
    assert r["upper"] == pytest.approx(4.0 + 3.0 * s)
    assert math.isnan(r["lower"]) and r["direction"] == "upper" and r["usable"]


def test_small_sample_threshold_is_the_student_prediction_bound() -> None:
    # k = 1.6449 (one-sided 95 % for a known σ), n = 4: the bound is
    # mean + t(3 dof, 0.95)·s·√(1 + 1/4) with t = 2.353 (t table, e.g. NIST e-Handbook
    # §1.3.6.7.2); pooled 1, 3, 5, 7: mean 4, s = sqrt(20/3)
    base = table({("sun", "sun", "FM4"): [1.0, 3.0, 5.0, 7.0]})
    r = row(thresholds(base, ThresholdRule(k=1.6449, sigma_floor=0.0, log_scale=False)),
            "sun", "FM4")
    bound = 4.0 + 2.353 * math.sqrt(20.0 / 3.0) * math.sqrt(1.25)
    assert r["upper"] == pytest.approx(bound, rel=2e-4)
    # the factor fades with n (→ 1) and a single sample keeps only the floor
    c = ThresholdRule().spread_factor(np.array([1, 3, 12, 1000]))
    assert c[0] == 1.0 and c[1] > c[2] > c[3] > 1.0 and c[3] == pytest.approx(1.0, abs=0.01)
    one = row(thresholds(table({("sun", "sun", "FM4"): [4.0]}), ThresholdRule(log_scale=False)),
              "sun", "FM4")
    assert one["sigma"] == pytest.approx(0.2) and one["usable"]


def test_default_rule_one_log_sample_per_record() -> None:
    """Default: each baseline record contributes the median of its blocks; a positive
    higher-is-worse indicator is thresholded on the logarithm (hand computation below), the
    floor is log(1 + f); a two-sided indicator stays linear."""
    recs = [[1.0, 3.0], [2.0, 2.0], [4.0, 6.0], [8.0, 8.5]]  # medians 2, 2, 5, 8.25
    base = [table({("sun", "sun", "FM4"): v, ("sun", "sun", "skewness"): [x - 3 for x in v]})
            for v in recs]
    rule = ThresholdRule(k=3.0, sigma_floor=0.05)
    th = thresholds(base, rule)
    r = row(th, "sun", "FM4")
    logs = np.log([2.0, 2.0, 5.0, 8.25])
    mu, s = logs.mean(), logs.std(ddof=1)
    c = float(rule.spread_factor(np.array([4]))[0])
    assert r["scale"] == "log" and r["n"] == 4
    assert r["mean"] == pytest.approx(math.exp(mu)) and r["std"] == pytest.approx(s)
    assert r["upper"] == pytest.approx(math.exp(mu + 3.0 * c * s))
    sk = row(th, "sun", "skewness")
    assert sk["scale"] == "linear" and sk["n"] == 4
    assert sk["mean"] == pytest.approx(np.mean([-1.0, -1.0, 2.0, 5.25]))
    # a deterministic baseline: the floor, 5 % in ratio
    flat = [table({("ring", "ring", "FM4"): [3.0, 3.0 + 1e-12]}) for _ in range(3)]
    f = row(thresholds(flat, rule), "ring", "FM4")
    assert f["upper"] == pytest.approx(3.0 * 1.05**3.0)


def test_sigma_floor_for_a_deterministic_baseline() -> None:
    # identical seeds: std 1e-12 → σ = 5 % of |μ| = 0.15, threshold 3 + 3·0.15 = 3.45
    base = table({("ring", "ring", "FM4"): [3.0, 3.0 + 1e-12, 3.0, 3.0 - 1e-12]})
    th = thresholds(base, ThresholdRule(k=3.0, sigma_floor=0.05, log_scale=False))
    r = row(th, "ring", "FM4")
    assert r["sigma"] == pytest.approx(0.15)
    assert r["upper"] == pytest.approx(3.45)
    # noise-level record does not alarm; a 20 % rise does
    v = judge(table({("ring", "ring", "FM4"): [3.0 + 1e-9] * 4}), th, ThresholdRule())
    assert v.components["ring"].state == "healthy"
    v = judge(table({("ring", "ring", "FM4"): [3.6] * 4}), th, ThresholdRule())
    assert v.components["ring"].state == "alarm"
    assert v.components["ring"].indicators["FM4"].margin == pytest.approx(3.6 / 3.45)


def test_two_sided_indicator_alarms_below_the_band() -> None:
    base = table({("sun", "sun", "skewness"): [-0.1, 0.1, -0.1, 0.1]})
    rule = ThresholdRule(k=3.0, sigma_floor=0.05, small_sample=False)
    th = thresholds(base, rule)
    r = row(th, "sun", "skewness")
    s = float(np.std([-0.1, 0.1, -0.1, 0.1], ddof=1))
    assert r["direction"] == "two-sided"
    assert r["lower"] == pytest.approx(-3 * s) and r["upper"] == pytest.approx(3 * s)
    v = judge(table({("sun", "sun", "skewness"): [-1.0] * 3}), th, rule)
    iv = v.components["sun"].indicators["skewness"]
    assert iv.alarm and iv.margin == pytest.approx(1.0 / (3 * s))


def test_verdict_median_over_blocks_alarms_and_unknown() -> None:
    base = table({
        ("sun", "sun", "FM4"): [3.0, 3.2, 2.8, 3.0],
        ("sun", "sun", "rms"): [1.0, 1.1, 0.9, 1.0],
        ("planet1", "planet", "FM4"): [3.0, 3.1, 2.9, 3.0],
        ("carrier", "shaft", "rms"): [np.nan] * 4,  # no usable threshold
    })
    rule = ThresholdRule()
    th = thresholds(base, rule)
    # one wild block does not move the median: sun FM4 blocks 9, 9, 9, 3 → median 9 alarms;
    # planet blocks 3, 3, 3, 30 → median 3 stays healthy
    rec = table({
        ("sun", "sun", "FM4"): [9.0, 9.0, 9.0, 3.0],
        ("sun", "sun", "rms"): [1.0, 1.0, 1.0, 1.0],
        ("planet1", "planet", "FM4"): [3.0, 3.0, 3.0, 30.0],
        ("carrier", "shaft", "rms"): [1.0] * 4,
        ("ring", "ring", "FM4"): [3.0] * 4,  # not in the baseline
    })
    assert record_values(rec).set_index(["component", "indicator"]).loc[
        ("planet1", "FM4"), "value"] == 3.0
    v = judge(rec, th, rule, machine="m", expected_faults=[])
    assert v.components["sun"].state == "alarm"
    assert v.components["sun"].alarms == ["FM4"]
    assert v.components["sun"].worst[0] == "FM4"
    assert v.components["planet1"].state == "healthy"
    assert v.components["carrier"].state == "unknown"
    assert v.components["ring"].state == "unknown"
    assert v.alarms == ["sun"]
    s = v.summary()
    assert s["counts"] == {"healthy": 1, "alarm": 1, "uncertain": 0, "unknown": 2}
    assert s["unexpected"] == ["sun"] and not s["localised"]


def test_component_not_analysed_is_unknown_with_the_reason() -> None:
    base = table({("sun", "sun", "FM4"): [3.0, 3.1, 2.9]})
    rule = ThresholdRule()
    v = judge(table({("sun", "sun", "FM4"): [3.0]}), thresholds(base, rule), rule,
              components=[("carrier", "shaft"), ("sun", "sun")],
              notes=["carrier: less than one revolution in the record; left out"])
    assert list(v.components) == ["carrier", "sun"]
    assert v.components["carrier"].state == "unknown"
    assert v.components["carrier"].kind == "shaft"
    assert v.to_dict()["notes"] == ["carrier: less than one revolution in the record; left out"]


def test_alarm_on_the_shaft_of_the_faulty_wheel_is_not_unexpected() -> None:
    base = table({("z42", "wheel", "SER"): [1.0, 1.1, 1.0, 1.1],
                  ("z53", "wheel", "SER"): [1.0, 1.1, 1.0, 1.1],
                  ("inter", "shaft", "FM4"): [3.0, 3.1, 3.0, 3.1]})
    rec = table({("z42", "wheel", "SER"): [5.0], ("z53", "wheel", "SER"): [1.0],
                 ("inter", "shaft", "FM4"): [6.0]})
    rule = ThresholdRule()
    fault = ConfiguredFault("z42", "wheel", "crack", "gear_geometry[1]", shaft="inter")
    s = judge(rec, thresholds(base, rule), rule, expected_faults=[fault]).summary()
    assert s["alarms"] == ["z42", "inter"]
    assert s["unexpected"] == [] and s["missed"] == [] and s["localised"]
    rec.loc[rec["component"] == "z53", "value"] = 5.0  # the wheel sharing the shaft alarms
    s = judge(rec, thresholds(base, rule), rule, expected_faults=[fault]).summary()
    assert s["unexpected"] == ["z53"] and not s["localised"]


def test_verdict_json_schema(tmp_path) -> None:
    base = table({("sun", "sun", "FM4"): [3.0, 3.1, 2.9], ("sun", "sun", "NA4"): [3.0] * 3})
    rule = ThresholdRule(k=2.5, sigma_floor=0.1)
    v = judge(table({("sun", "sun", "FM4"): [5.0]}), thresholds(base, rule), rule,
              machine="reclaimer", baseline={"seeds": [0, 1, 2]}, record_info={"seed": 100})
    path = v.write(tmp_path)
    assert path.name == "verdict.json"
    text = path.read_text()
    assert "NaN" not in text  # strict JSON
    d = read_verdict(tmp_path)
    assert d["schema"] == "geardyn.verdict/1"
    assert d["machine"] == "reclaimer" and d["channels"] == ["acc"]
    assert d["k"] == 2.5 and d["sigma_floor"] == 0.1 and "2.5·σ" in d["rule"]
    assert d["baseline"]["seeds"] == [0, 1, 2] and d["record"]["seed"] == 100
    ind = d["components"]["sun"]["indicators"]["FM4"]
    assert set(ind) >= {"value", "threshold", "mean", "std", "margin", "alarm"}
    assert ind["alarm"] is True and d["components"]["sun"]["state"] == "alarm"
    assert "NA4" not in d["components"]["sun"]["indicators"]  # no record value
    assert d["summary"]["alarms"] == ["sun"]
    assert d["expected_faults"] is None and "localised" not in d["summary"]
    json.dumps(d, allow_nan=False)


def test_several_channels_are_kept_apart() -> None:
    base = pd.concat([table({("sun", "sun", "FM4"): [3.0, 3.0]}, "acc"),
                      table({("sun", "sun", "FM4"): [10.0, 10.0]}, "ias")])
    th = thresholds(base)
    assert len(th) == 2
    rec = pd.concat([table({("sun", "sun", "FM4"): [3.0]}, "acc"),
                     table({("sun", "sun", "FM4"): [20.0]}, "ias")])
    v = judge(rec, th, ThresholdRule())
    assert v.channels == ["acc", "ias"]
    assert v.components["sun"].alarms == ["ias:FM4"]


def test_bad_inputs_name_the_field() -> None:
    with pytest.raises(InputError, match="k: threshold factor"):
        ThresholdRule(k=0)
    with pytest.raises(InputError, match="sigma_floor"):
        ThresholdRule(sigma_floor=1.5)
    with pytest.raises(InputError, match="missing column.*block"):
        thresholds(pd.DataFrame({"component": ["a"], "kind": ["sun"], "indicator": ["FM4"],
                                 "value": [1.0], "channel": ["x"]}))
    with pytest.raises(InputError, match="no indicator table"):
        thresholds([])


def test_healthy_variant_and_fault_list_planetary() -> None:
    cfg = geardyn.load_config(EXAMPLES / "planetary_reclaimer.toml")
    faults = fault_list(cfg)
    assert [(f.component, f.kind, f.shaft) for f in faults] == [("planetary.sun", "wheel", "sun")]
    assert "20%" in faults[0].description
    assert faults[0].field == "planetary_dynamics.stages[0].faults[0]"
    healthy = healthy_variant(cfg)
    assert fault_list(healthy) == []
    assert healthy.planetary_dynamics.stages[0].transmission_error  # the rest is kept
    assert cfg.planetary_dynamics.stages[0].faults  # the input is not modified


def test_healthy_variant_and_fault_list_transmission() -> None:
    data = geardyn.load_config(EXAMPLES / "seed002_transmission.toml").model_dump()
    data["transmission"]["bearings"][1]["outer_spall"] = {
        "angle_deg": 270.0, "angular_length_deg": 5.0, "depth_m": 1e-4}
    low = next(g for g in data["gear_geometry"] if g["pair"] == "low")
    low["cracks"] = [{"gear": "a", "depth_m": 1e-3}]
    cfg = parse_config(data)
    got = {(f.component, f.kind, f.shaft) for f in fault_list(cfg)}
    assert got == {("intermediate/z42", "wheel", "intermediate"),
                   ("output roller", "bearing", "output")}
    assert fault_list(healthy_variant(cfg)) == []


def test_margin_of_a_negative_threshold_exceeds_one_only_on_alarm() -> None:
    base = table({("sun", "sun", "FM4"): [-2.0, -2.2, -1.8, -2.0]})
    rule = ThresholdRule(small_sample=False)
    th = thresholds(base, rule)
    assert row(th, "sun", "FM4")["upper"] < 0
    low = judge(table({("sun", "sun", "FM4"): [-3.0]}), th, rule).components["sun"]
    high = judge(table({("sun", "sun", "FM4"): [0.0]}), th, rule).components["sun"]
    assert low.state == "healthy" and low.indicators["FM4"].margin < 0
    assert high.state == "alarm" and high.indicators["FM4"].margin > 1


def test_isolation_evidence_is_reported_apart_from_the_worst_detection_indicator() -> None:
    from dataclasses import replace

    from geardyn.diagnosis.verdict import is_isolation_measure

    base = table({("sun", "sun", "FM4"): [3.0, 3.1, 2.9, 3.0]})
    rule = ThresholdRule()
    v = judge(table({("sun", "sun", "FM4"): [3.2]}), thresholds(base, rule), rule)
    fm4 = v.components["sun"].indicators["FM4"]
    v.components["sun"].indicators["SDR"] = replace(fm4, value=9.0, threshold=2.0, margin=4.5,
                                                    alarm=True)
    row_ = v.table().iloc[0]
    assert row_["worst_indicator"] == "FM4" and row_["isolation"] == "SDR"
    assert row_["isolation_margin"] == 4.5
    names = ("SDR", "SDR_TE", "BPFO concentration", "acc:SDR", "FM4", "SER")
    assert [is_isolation_measure(n) for n in names] == [True, True, True, True, False, False]
