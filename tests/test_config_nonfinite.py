"""Non-finite numbers are input errors in every config section (issue 13 item 1, first part):
each is refused with the field's path, never a deep LinAlgError or a silent exit 0."""

from __future__ import annotations

import pytest

from geardyn.config import load_config
from geardyn.errors import ConfigError


@pytest.mark.parametrize(
    ("example", "old", "new", "field"),
    [
        ("planetary_reclaimer.toml", "sun = 32.4263", "sun = nan", "input_speeds_rpm.sun"),
        ("planetary_reclaimer.toml", "mass_kg = 98.9691", "mass_kg = inf",
         "planetary_dynamics.stages[0].sun.mass_kg"),
        ("seed002_transmission.toml", "position_m = [0.0, 0.0]", "position_m = [nan, 0.0]",
         "transmission.shafts[0] 'output'.position_m[0]"),
        ("seed002_two_stage.toml", "normal_module_m = 0.003", "normal_module_m = -inf",
         "normal_module_m"),
        ("seed004_diagnose_sun_crack.toml", "noise_rms = 0.01", "noise_rms = nan",
         "sensors[0] 'ring_acc'.noise_rms"),
        ("reclaimer_drive.toml", "shaft_angle_deg = 90", "shaft_angle_deg = nan",
         "shaft_angle_deg"),
    ],
)
def test_non_finite_values_name_the_field(tmp_path, examples_dir, example, old, new, field):
    text = (examples_dir / example).read_text()
    assert old in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(old, new, 1))
    with pytest.raises(ConfigError) as err:
        load_config(bad)
    assert field in str(err.value)
    assert "finite" in str(err.value)
