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


def test_implausible_inputs_are_refused(tmp_path, examples_dir):
    """Issue 13 examples: a module typed in mm into an m field; a time step longer than the
    run."""
    text = (examples_dir / "seed002_two_stage.toml").read_text()
    bad = tmp_path / "m.toml"
    bad.write_text(text.replace("normal_module_m = 0.003", "normal_module_m = 3"))
    with pytest.raises(ConfigError, match=r"normal_module_m: Input should be less than or "
                       r"equal to 0.1"):
        load_config(bad)
    text = (examples_dir / "planetary_reclaimer.toml").read_text()
    bad.write_text(text.replace("dt_s = 1e-4", "dt_s = 1.0"))
    with pytest.raises(ConfigError, match="dt_s: the time step 1 s must be shorter than "
                       "t_end_s 0.05 s"):
        load_config(bad)


def test_far_too_large_time_step_is_refused_before_the_run(tmp_path, examples_dir):
    """Issue 13: a 100× too-large step ran to 'ok' with 0.17 m mesh deflections. Now the step is
    checked against the shortest natural period before anything runs: refused naming dt_s and
    the limit, no output file (the 'suspect' status of a run that passes this check but deflects
    too far is tested in tests/robust/test_sanity.py)."""
    from typer.testing import CliRunner

    from geardyn.cli import app

    text = (examples_dir / "planetary_reclaimer.toml").read_text()
    cfg = tmp_path / "big_step.toml"
    cfg.write_text(text.replace("dt_s = 1e-4", "dt_s = 1e-2").replace("t_end_s = 0.05",
                                                                      "t_end_s = 0.5"))
    out = tmp_path / "run.nc"
    r = CliRunner().invoke(app, ["simulate", str(cfg), "--out", str(out)])
    assert r.exit_code == 2, r.output
    text_out = " ".join(r.output.split())
    assert "planetary_dynamics.simulation.dt_s" in text_out and "too large" in text_out
    assert "Traceback" not in r.output
    assert not out.exists()
    r = CliRunner().invoke(app, ["simulate", str(examples_dir / "planetary_reclaimer.toml"),
                                 "--out", str(tmp_path / "ok.nc")])
    assert r.exit_code == 0, r.output
