"""Sweep specs: expansion, seeds, draws and the errors of bad specs (nothing runs)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from geardyn.errors import ConfigError
from geardyn.sweep.spec import case_seed, from_dict, get_path, load_spec, parse_path

ROOT = Path(__file__).resolve().parents[2]
BASE = str(ROOT / "examples" / "seed004_diagnose_sun_crack.toml")
CRACK = "planetary_dynamics.stages[0].faults[0].crack_fraction"


def spec(*axes: dict, **sweep: object) -> dict:
    return {"sweep": {"base": BASE, "seed": 5, **sweep}, "axes": list(axes),
            "outputs": {"indicators": {"enabled": False}}}


def problems(data: dict) -> str:
    with pytest.raises(ConfigError) as info:
        from_dict(data)
    return str(info.value)


def test_product_order_replicates_and_labels() -> None:
    sw = from_dict(spec({"name": "crack", "path": CRACK, "values": [0.1, 0.2]},
                        {"name": "sun_rpm", "path": "input_speeds_rpm.sun",
                         "range": {"start": 30.0, "stop": 40.0, "num": 3}},
                        replicates=2))
    assert len(sw.cases) == 2 * 3 * 2
    labels = [(c.labels(sw.axes)["crack"], c.labels(sw.axes)["sun_rpm"], c.replicate)
              for c in sw.cases]
    # first axis slowest, replicate fastest (itertools.product order)
    assert labels[:4] == [(0.1, 30.0, 0), (0.1, 30.0, 1), (0.1, 35.0, 0), (0.1, 35.0, 1)]
    assert labels[-1] == (0.2, 40.0, 1)
    cfg = sw.case_config(sw.cases[-1])
    assert get_path(cfg, CRACK) == 0.2 and cfg["input_speeds_rpm"]["sun"] == 40.0
    assert get_path(sw.base, CRACK) == 0.2  # the base is not modified


def test_zip_groups_and_zip_combination() -> None:
    a = {"name": "gear", "path": "planetary_dynamics.stages[0].faults[0].gear",
         "values": ["sun", "ring", "planet"], "group": "f"}
    b = {"name": "crack", "path": CRACK, "values": [0.1, 0.2, 0.3], "group": "f"}
    c = {"name": "sun_rpm", "path": "input_speeds_rpm.sun", "values": [30.0, 35.0]}
    sw = from_dict(spec(a, b, c))
    assert len(sw.cases) == 6
    pairs = {(x.labels(sw.axes)["gear"], x.labels(sw.axes)["crack"]) for x in sw.cases}
    assert pairs == {("sun", 0.1), ("ring", 0.2), ("planet", 0.3)}
    sw = from_dict(spec(a, b, combine="zip"))
    assert [x.labels(sw.axes)["crack"] for x in sw.cases] == [0.1, 0.2, 0.3]


def test_case_seed_rule() -> None:
    """Per-case seed = first word of SeedSequence([sweep seed, case index]): independent of the
    order cases run in, so any case can be re-run alone."""
    sw = from_dict(spec({"name": "crack", "path": CRACK, "values": [0.1, 0.2, 0.3]},
                        replicates=2))
    seeds = [c.seed for c in sw.cases]
    assert seeds == [int(np.random.SeedSequence([5, i]).generate_state(1)[0])
                     for i in range(6)]
    assert len(set(seeds)) == 6
    assert case_seed(5, 3) == seeds[3] and case_seed(6, 3) != seeds[3]


def test_range_step_and_uniform_draw_reproducible() -> None:
    sw = from_dict(spec({"name": "sun_rpm", "path": "input_speeds_rpm.sun",
                         "range": {"start": 30.0, "stop": 31.0, "step": 0.25}}))
    assert [a for a in sw.axes[0].values] == [30.0, 30.25, 30.5, 30.75, 31.0]
    draw = {"name": "crack", "path": CRACK, "sample": {"low": 0.1, "high": 0.3, "n": 5}}
    v1 = from_dict(spec(draw)).axes[0].values
    assert v1 == from_dict(spec(draw)).axes[0].values
    assert all(0.1 <= v < 0.3 for v in v1)
    assert v1 != from_dict(spec(draw, seed=6)).axes[0].values


def test_latin_hypercube_one_value_per_stratum() -> None:
    """McKay et al. 1979: each of the n equal strata of every axis holds exactly one value."""
    n = 8
    axes = [{"name": "crack", "path": CRACK, "group": "g",
             "sample": {"low": 0.0, "high": 0.4, "n": n, "method": "latin_hypercube"}},
            {"name": "sun_rpm", "path": "input_speeds_rpm.sun", "group": "g",
             "sample": {"low": 30.0, "high": 34.0, "n": n, "method": "latin_hypercube"}}]
    sw = from_dict(spec(*axes))
    assert len(sw.cases) == n  # one group: zipped, not n²
    for ax, (lo, hi) in zip(sw.axes, [(0.0, 0.4), (30.0, 34.0)], strict=True):
        strata = sorted(int(math.floor((v - lo) / (hi - lo) * n)) for v in ax.values)
        assert strata == list(range(n))


def test_quoted_keys_in_paths() -> None:
    assert parse_path('a.b[0]["sun.x"].c') == ["a", "b", 0, "sun.x", "c"]
    sw = from_dict(spec({"name": "damp", "values": [100.0, 200.0],
                         "path": 'planetary_dynamics.simulation.support_damping["sun.x"]'}))
    cfg = sw.case_config(sw.cases[1])
    assert cfg["planetary_dynamics"]["simulation"]["support_damping"]["sun.x"] == 200.0


def test_unknown_path_names_the_axis() -> None:
    msg = problems(spec({"name": "crak", "values": [0.1],
                         "path": "planetary_dynamics.stages[0].faults[0].crak_fraction"}))
    assert "axis 'crak'" in msg and "no field 'crak_fraction'" in msg
    msg = problems(spec({"name": "f2", "path": "planetary_dynamics.stages[0].faults[3].gear",
                         "values": ["sun"]}))
    assert "axis 'f2'" in msg and "index [3] does not exist" in msg


def test_wrong_type_names_the_axis() -> None:
    msg = problems(spec({"name": "crack", "path": CRACK, "values": [0.1, "big"]}))
    assert "axis 'crack'" in msg and "'big' is not a number" in msg


def test_empty_axis_rejected() -> None:
    msg = problems(spec({"name": "crack", "path": CRACK, "values": []}))
    assert "axes[0] 'crack'" in msg and "values: the axis is empty" in msg


def test_too_many_cases_rejected() -> None:
    msg = problems(spec({"name": "crack", "path": CRACK,
                         "range": {"start": 0.0, "stop": 0.5, "num": 50}},
                        {"name": "sun_rpm", "path": "input_speeds_rpm.sun",
                         "range": {"start": 30.0, "stop": 40.0, "num": 30}},
                        replicates=10))
    assert "15000 cases" in msg and "max_cases = 10000" in msg and "crack 50" in msg


def test_value_making_a_case_invalid_names_axis_and_case() -> None:
    msg = problems(spec({"name": "crack", "path": CRACK, "values": [0.1, 1.5]}))
    assert "case 1" in msg and "axis 'crack' = 1.5" in msg and "less than 1" in msg


def test_zip_lengths_and_other_spec_errors() -> None:
    a = {"name": "gear", "path": "planetary_dynamics.stages[0].faults[0].gear",
         "values": ["sun", "ring"], "group": "f"}
    b = {"name": "crack", "path": CRACK, "values": [0.1, 0.2, 0.3], "group": "f"}
    assert "group 'f': zipped axes need equal lengths" in problems(spec(a, b))
    assert "unknown field" in problems({**spec(b), "sweep": {"base": BASE, "sed": 1}})
    assert "give exactly one of values, range or sample" in problems(
        spec({"name": "crack", "path": CRACK}))
    bad = spec(b)
    bad["outputs"]["channels"] = {"names": ["no_such_sensor"]}
    assert "'no_such_sensor' is not a sensor" in problems(bad)
    assert "axis names must be distinct" in problems(spec(b, {**b, "group": None}))


def test_example_spec_is_valid() -> None:
    sw = load_spec(ROOT / "examples" / "sweeps" / "seed004_fault_dataset.toml")
    assert len(sw.cases) == 10 * 2 * 3
    healthy = [c for c in sw.cases if c.labels(sw.axes)["fault_gear"] == "none"]
    assert len(healthy) == 2 * 3
    assert all(get_path(sw.case_config(c), CRACK) == 0.0 for c in healthy)


def _with_verdicts(**opts: object) -> dict:
    data = spec({"name": "crack", "path": CRACK, "values": [0.0, 0.1]})
    data["outputs"] = {"verdicts": {"healthy": {"crack": 0.0}, **opts}}
    return data


@pytest.mark.parametrize(("value", "rule"), [
    (0.0, "greater than 0"), (1.0, "less than 1"), (-0.01, "greater than 0"),
    (1.5, "less than 1"), (math.nan, "finite"), ("one percent", "valid number")])
def test_bad_false_alarm_probability_named(value: object, rule: str) -> None:
    """The stated false-alarm probability of the sweep verdicts must lie in (0, 1): the error
    names the option and the rule broken, nothing runs."""
    msg = problems(_with_verdicts(false_alarm_probability=value))
    assert "outputs.verdicts.false_alarm_probability" in msg and rule in msg, msg


def test_verdict_options_defaults_and_other_errors() -> None:
    v = from_dict(_with_verdicts()).spec.outputs.verdicts
    assert v.false_alarm_probability == 0.01 and v.threshold_k is None  # as [diagnosis]
    assert v.localisation_confidence == 0.95
    msg = problems(_with_verdicts(threshold_k=0.0))
    assert "outputs.verdicts.threshold_k" in msg and "greater than 0" in msg
    msg = problems(_with_verdicts(localisation_confidence=0.4))
    assert "outputs.verdicts.localisation_confidence" in msg and "0.5" in msg
    data = _with_verdicts()
    data["axes"][0]["name"] = "tests"  # a stored verdict variable
    data["outputs"]["verdicts"]["healthy"] = {"tests": 0.0}
    assert "tests are the names of verdict variables" in problems(data)
