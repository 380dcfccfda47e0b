"""Unit strings are parsed, never evaluated (issue 20): grammar NUMBER [UNIT], bounded length,
whole powers ≤ 4, no powers of powers, no division by zero; the dimension checked against the
field; dimensionless units (ppm, percent) only in dimensionless fields; the field named.

Expected values are exact unit definitions (SI brochure: 1 g/cm³ = 1000 kg/m³, 1 rpm = 1/60 Hz,
1 percent = 0.01, 1 ppm = 1e-6)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from geardyn.config.loader import load_config
from geardyn.config.units import MAX_TEXT, SUFFIXES, parse_quantity, to_unit
from geardyn.errors import ConfigError
from geardyn.templates import render


@pytest.mark.parametrize(("text", "unit", "want"), [
    ("7.8 g/cm**3", "kg/m**3", 7800.0),
    ("2 kg m^2", "kg*m**2", 2.0),
    ("1.5 N·m", "N*m", 1.5),
    ("3 1/min", "rpm", 3.0),
    ("1 turn/s", "Hz", 1.0),
    ("20 µm", "m", 20e-6),
    ("-3 mm", "m", -0.003),
    ("5 percent", "dimensionless", 0.05),
    ("5 %", "dimensionless", 0.05),
    ("200 ppm", "dimensionless", 200e-6),
    ("0.05", "dimensionless", 0.05),
])
def test_unit_strings_convert(text, unit, want):
    assert to_unit(text, unit, "x") == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize(("text", "unit", "what", "rule"), [
    ("32.4263 ppm", "rpm", "a rotational speed", "ppm is dimensionless"),
    ("40.8 percent", "m", "a length", "percent is dimensionless"),
    ("30 percent", "deg", "an angle", "percent is dimensionless"),
    ("5 ppm", "kg*m**2", "a moment of inertia", "ppm is dimensionless"),
    ("3 m", "dimensionless", "a dimensionless number", "expected a dimensionless unit"),
    ("1 rad", "dimensionless", "a dimensionless number", "expected a dimensionless unit"),
    ("5 rad", "N*m", "a torque", "not a torque"),
    ("3 m / 0", "m", "a length", "division by zero"),
    ("3 m/s/0.0", "m", "a length", "division by zero"),
    ("10**10**9 mm", "m", "a length", "powers of powers"),
    ("3 m**2**3", "m", "a length", "powers of powers"),
    ("3 m**9", "m", "a length", "power 9 is above 4"),
    ("3 m**0.5", "m", "a length", "whole number"),
    ("1e999 m", "m", "a length", "not a finite number"),
    ("nan m", "m", "a length", "expected a number followed by a unit"),
    ("2*3 m", "m", "a length", "expected a number followed by a unit"),
    ("(3 m)", "m", "a length", "expected a number followed by a unit"),
    ("3 frobs", "m", "a length", "not a number with a unit"),
    ("3 " + "m*" * 60 + "m", "m", "a length", f"longer than {MAX_TEXT} characters"),
])
def test_unit_strings_refused_with_the_rule(text, unit, what, rule):
    with pytest.raises(ValueError, match=rule.replace("(", r"\(")):
        to_unit(text, unit, what)


def test_the_grammar_does_not_evaluate():
    assert parse_quantity("  3.5e2   kg m^2 ") == (350.0, "kg m**2")
    assert parse_quantity("4") == (4.0, None)
    with pytest.raises(ValueError):
        parse_quantity("__import__('os') m")


def test_a_power_tower_does_not_hang():
    """``10**10**9`` is refused by the grammar before pint sees it (was: the power computed);
    a fresh interpreter (so nothing is cached) finishes well inside 60 s."""
    code = ("from geardyn.config.units import to_unit\n"
            "try:\n    to_unit('10**10**9 mm', 'm', 'a length')\n"
            "except ValueError as e:\n    print('refused:', e)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60, check=True).stdout
    assert "powers of powers" in out


@pytest.mark.parametrize("suffix", list(SUFFIXES))
def test_every_suffix_refuses_dimensionless_units(suffix):
    info = SUFFIXES[suffix]
    with pytest.raises(ValueError, match="dimensionless"):
        to_unit("12 ppm", info.unit, info.what)
    with pytest.raises(ValueError, match="dimensionless"):
        to_unit("12 percent", info.unit, info.what)


def _config(tmp_path, old: str, new: str):
    text = render("parallel", "u.toml")
    assert old in text
    path = tmp_path / "u.toml"
    path.write_text(text.replace(old, new))
    return path


def test_ppm_speed_in_a_config_names_the_field(tmp_path):
    path = _config(tmp_path, "input = 1470.0", 'input = "32.4263 ppm"')
    with pytest.raises(ConfigError) as exc:
        load_config(path)
    msg = str(exc.value)
    assert "input_speeds_rpm.input" in msg and "ppm is dimensionless" in msg


def test_percent_length_names_that_field_only(tmp_path):
    path = _config(tmp_path, "normal_module_m = 0.003", 'normal_module_m = "40.8 percent"')
    with pytest.raises(ConfigError) as exc:
        load_config(path)
    lines = [x for x in str(exc.value).splitlines() if x.strip()]
    bad = [x for x in lines if "normal_module_m" in x]
    assert bad and "percent is dimensionless" in bad[0]
    assert all("normal_module_m" in x for x in lines if "percent" in x or "dimension" in x)


def test_percent_in_a_dimensionless_field():
    import tomllib

    from geardyn.config.loader import parse_config

    data = tomllib.loads(render("planetary", "p.toml"))
    data["planetary_dynamics"]["simulation"]["modal_damping_ratio"] = "2 percent"
    cfg = parse_config(data)
    assert cfg.planetary_dynamics.simulation.modal_damping_ratio == pytest.approx(0.02)
    data["planetary_dynamics"]["simulation"]["modal_damping_ratio"] = "2 mm"
    with pytest.raises(ConfigError, match=r"modal_damping_ratio: '2 mm' is not a dimensionless"):
        parse_config(data)
