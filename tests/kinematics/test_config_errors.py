"""Malformed mechanism descriptions are rejected with a message naming the item and the rule."""

from __future__ import annotations

import copy
import tomllib

import pytest

from geardyn import analyze_kinematics
from geardyn.config import load_config, parse_config
from geardyn.errors import ConfigError, InputError

SIMPLE = """
name = "simple planetary"
frame = "housing"
links = ["housing", "sun", "carrier"]

[[planetary]]
name = "ps"
sun = "sun"
ring = "housing"
carrier = "carrier"
sun_teeth = 16
planet_teeth = 24
ring_teeth = 65
n_planets = 3
"""


def base() -> dict:
    return tomllib.loads(SIMPLE)


def reject(data: dict, *fragments: str) -> str:
    with pytest.raises(ConfigError) as exc:
        parse_config(data)
    msg = str(exc.value)
    for frag in fragments:
        assert frag in msg, f"{frag!r} not in {msg!r}"
    assert "Traceback" not in msg
    return msg


def test_valid_base_config_loads():
    cfg = parse_config(base())
    assert analyze_kinematics(cfg).dof == 1


def test_unknown_link_in_gear_pair():
    d = base()
    d["gear_pairs"] = [
        {"name": "extra", "a": {"link": "sun", "teeth": 20}, "b": {"link": "shaftX", "teeth": 30}}
    ]
    reject(d, "gear_pairs[0] 'extra'", "unknown link 'shaftX'")


def test_gear_pair_without_common_carrier():
    d = {
        "frame": "f",
        "links": ["f", "s", "c", "p", "q"],
        "turning_pairs": [
            {"links": ["f", "s"], "axis": 1},
            {"links": ["f", "c"], "axis": 1},
            {"links": ["c", "p"], "axis": 2},
            {"links": ["p", "q"], "axis": 3},
        ],
        "gear_pairs": [
            {"name": "sq", "a": {"link": "s", "teeth": 20}, "b": {"link": "q", "teeth": 20}},
        ],
    }
    reject(d, "gear pair 'sq'", "no common carrier", "eq 1")


def test_gear_pair_with_two_carriers():
    d = {
        "frame": "f",
        "links": ["f", "sun", "ring", "c"],
        "turning_pairs": [
            {"links": ["f", "sun"], "axis": "central"},
            {"links": ["f", "ring"], "axis": "central"},
            {"links": ["f", "c"], "axis": "central"},
        ],
        "gear_pairs": [
            {
                "name": "sr",
                "a": {"link": "sun", "teeth": 20},
                "b": {"link": "ring", "teeth": 60, "internal": True},
            },
        ],
    }
    reject(d, "gear pair 'sr'", "two or more carriers")


def test_non_integer_teeth():
    d = base()
    d["planetary"][0]["sun_teeth"] = 16.5
    reject(d, "planetary[0] 'ps'.sun_teeth", "whole number")


def test_zero_teeth():
    d = base()
    d["planetary"][0]["planet_teeth"] = 0
    reject(d, "planetary[0] 'ps'.planet_teeth", "greater than or equal to 1")


def test_planets_cannot_be_equally_spaced():
    d = base()
    d["planetary"][0]["ring_teeth"] = 64
    reject(d, "planetary[0] 'ps'", "cannot be equally spaced", "(16 + 64)/3")


def test_planets_overlap():
    d = base()
    d["planetary"][0].update(sun_teeth=12, planet_teeth=30, ring_teeth=72, n_planets=4)
    reject(d, "planetary[0] 'ps'", "adjacent planet tips overlap")


def test_unknown_field_is_a_typo():
    d = base()
    d["planetary"][0]["n_planet"] = 3
    reject(d, "planetary[0] 'ps'.n_planet", "unknown field")


def test_duplicate_link():
    d = base()
    d["links"] = ["housing", "sun", "carrier", "sun"]
    reject(d, "duplicate link name 'sun'")


def test_unknown_frame():
    d = base()
    d["frame"] = "casing"
    reject(d, "frame: unknown link 'casing'")


def test_floating_link():
    d = base()
    d["links"].append("idler")
    reject(d, "link 'idler'", "no turning pair")


def test_internal_gear_with_external_pitch_angle():
    d = base()
    d["gear_pairs"] = [
        {
            "name": "bad",
            "a": {"link": "sun", "teeth": 20, "internal": True, "pitch_angle_deg": 30},
            "b": {"link": "carrier", "teeth": 30},
        }
    ]
    reject(d, "gear_pairs[0] 'bad'.a", "internal gear needs 90 < |θ| ≤ 180")


def test_bearing_without_turning_pair_and_bad_geometry():
    d = base()
    d["links"].append("shaft")
    d["turning_pairs"] = [{"links": ["shaft", "housing"], "axis": "s"}]
    d["bearings"] = [
        {
            "name": "b1",
            "inner": "shaft",
            "outer": "carrier",
            "n_elements": 9,
            "element_diameter_m": 0.008,
            "pitch_diameter_m": 0.04,
        },
    ]
    reject(d, "bearing 'b1'", "no turning pair between 'shaft' and 'carrier'")
    d["bearings"][0].update(outer="housing", element_diameter_m=0.05)
    reject(d, "bearings[0] 'b1'", "element_diameter_m", "must be smaller than pitch_diameter_m")


def test_turning_pair_on_one_link_and_conflicting_axes():
    d = base()
    d["turning_pairs"] = [{"links": ["sun", "sun"], "axis": 1}]
    reject(d, "turning_pairs[0].links", "two different links")
    d["turning_pairs"] = [
        {"links": ["sun", "housing"], "axis": 7},
        {"links": ["housing", "sun"], "axis": 8},
    ]
    reject(d, "turning pair housing–sun given twice with different axis levels")


def test_unknown_input_and_frame_input():
    d = base()
    d["input_speeds_rpm"] = {"motor": 1000.0}
    reject(d, "input_speeds_rpm: unknown link 'motor'")
    d["input_speeds_rpm"] = {"housing": 1000.0}
    reject(d, "input_speeds_rpm: 'housing' is the frame")


def test_inputs_that_do_not_fix_the_motion(examples_dir):
    diff = analyze_kinematics(load_config(examples_dir / "car_differential.toml"))
    with pytest.raises(InputError, match="2 degree\\(s\\) of freedom"):
        diff.velocity_ratios(["left_wheel"])
    # drive pinion and cage are tied (ω2 = −5 ω7): together they leave one motion free
    with pytest.raises(InputError, match="do not fix the motion"):
        diff.velocity_ratios(["drive_pinion", "cage"])
    with pytest.raises(InputError, match="input link 'wheel': unknown link"):
        diff.velocity_ratios(["wheel", "cage"])


def test_not_toml_and_missing_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("frame = \n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_config(bad)
    with pytest.raises(ConfigError, match="does not exist"):
        load_config(tmp_path / "nope.toml")


def test_several_problems_are_all_reported():
    d = copy.deepcopy(base())
    d["links"] += ["idler", "idler2"]
    msg = reject(d, "link 'idler'", "link 'idler2'")
    assert msg.count("no turning pair") == 2
