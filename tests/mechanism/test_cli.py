"""``geardyn modes`` and ``geardyn simulate`` on the [dynamics] model of a mechanism."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.config import load_config
from geardyn.results import is_result
from geardyn.run import run_simulation

runner = CliRunner()


def test_modes_of_the_three_stage_gearbox(examples_dir, tmp_path):
    out = tmp_path / "modes.nc"
    res = runner.invoke(app, ["modes", str(examples_dir / "three_stage_gearbox.toml"),
                              "--netcdf", str(out)])
    assert res.exit_code == 0, res.output
    assert "torsional model of the mechanism" in res.output
    ds = xr.open_dataset(out)
    f = ds["frequency"].values
    assert f[0] == 0.0 and (f[1:] > 0).all()  # one rigid mode: the kinematic DOF
    # N − 1 = 2 degenerate planet modes per 3-planet stage (Lin & Parker 1999)
    assert (ds["multiplicity"].values == 2).sum() == 4
    ds.close()


def test_simulate_writes_the_result_layout(examples_dir, tmp_path):
    out = tmp_path / "run.nc"
    res = runner.invoke(app, ["simulate", str(examples_dir / "car_differential_dynamics.toml"),
                              "--out", str(out), "--t-end", "0.05"])
    assert res.exit_code == 0, res.output
    ds = xr.open_dataset(out)
    assert is_result(ds) and ds.attrs["model"] == "mechanism"
    assert ds["time"].values[-1] == pytest.approx(0.05)
    assert {"left_wheel", "right_wheel", "cage", "drive_pinion"} <= set(ds["shaft"].values)
    # car turning right at 30 km/h (seed 000 eq 8): the cage turns at the wheels' mean speed
    w = ds["speed"].sel(time=slice(0.03, None)).mean("time")
    assert float(w.sel(shaft="cage")) == pytest.approx(28.0, rel=2e-2)
    assert ds["mesh_force"].attrs["units"] == "N"
    ds.close()


def test_run_simulation_dispatches_and_overrides_the_run_end(examples_dir):
    cfg = load_config(examples_dir / "alouette3_mgb_dynamics.toml")
    ds = run_simulation(cfg, t_end_s=0.01)
    assert ds.attrs["model"] == "mechanism" and ds.attrs["status"] == "ok"
    assert ds["time"].values[-1] == pytest.approx(0.01)
    rpm = ds["speed_rpm"].sel(shaft="input").values
    assert np.all(np.isfinite(rpm)) and math.isclose(rpm[0], 6000.0, rel_tol=1e-9)


def test_run_simulation_measures_the_mechanism_with_its_sensors(examples_dir):
    """Encoder and tacho channels on links of the whole seed 004 drive (add_sensors)."""
    import tomllib

    from geardyn.config.loader import parse_config
    from geardyn.results import channel, channels

    d = tomllib.loads((examples_dir / "reclaimer_whole_drive.toml").read_text())
    d["sensors"] = [{"name": "wheel_enc", "kind": "encoder", "shaft": "bucket_wheel",
                     "pulses_per_rev": 1000, "clock_hz": 80e6},
                    {"name": "motor_tacho", "kind": "tacho", "shaft": "motor"}]
    ds = run_simulation(parse_config(d), t_end_s=0.3)
    assert set(channels(ds)) == {"wheel_enc", "motor_tacho"}
    tacho = channel(ds, "motor_tacho")
    # one pulse per motor-shaft revolution at ≈ 995 rpm
    period = float(np.median(np.diff(tacho.values)))
    assert 60.0 / period == pytest.approx(995.0, rel=5e-3)


def test_a_drive_on_a_carried_link_is_refused(examples_dir):
    import tomllib

    from geardyn.config.loader import parse_config
    from geardyn.errors import ConfigError

    d = tomllib.loads((examples_dir / "three_stage_gearbox.toml").read_text())
    d["dynamics"]["simulation"]["torques"].append({"body": "stage1.planet1", "torque_nm": 1.0})
    with pytest.raises(ConfigError, match=r"torques\[1\]: 'stage1.planet1' turns in another"):
        run_simulation(parse_config(d), t_end_s=0.01)


def test_lateral_model_modes_and_bearing_forces(examples_dir):
    """Lateral three-stage gearbox: mode types from the lateral share of each shape; the
    result carries one bearing force per direction, which balances the transmitted load."""
    import tomllib

    from geardyn.config.loader import parse_config
    from geardyn.models.core import model_from_config
    from geardyn.models.core.modal import core_modes
    from geardyn.models.core.simulate import simulate

    d = tomllib.loads((examples_dir / "three_stage_gearbox.toml").read_text())
    d["dynamics"]["lateral"] = True
    d["dynamics"]["links"] = [{"link": x, "bearing_n_per_m": 2e9} for x in
                              ("low_speed_carrier", "s1", "s2", "output")]
    d["dynamics"]["links"] += [{"link": f"stage{s}.planet{i}", "bearing_n_per_m": 1e9}
                               for s in (1, 2) for i in (1, 2, 3)]
    cfg = parse_config(d)
    res = core_modes(model_from_config(cfg))
    assert res.mode_type[0] == "rigid"
    assert res.mode_type[1] == "torsional"  # the 2 Hz rotor-on-main-shaft mode
    assert "coupled" in res.mode_type  # the parallel stage couples rotation and translation
    ds = simulate(cfg, t_end_s=0.02)
    assert ds.attrs["status"] == "ok"
    assert "output.bearing.x" in ds["bearing"].values
    assert ds["bearing_force"].attrs["units"] == "N"
    # the pinion of stage 3 is pushed by its mesh force: the bearing reacts it (|F| > 0)
    f = ds["bearing_force"].sel(bearing=["output.bearing.x", "output.bearing.y"]).values[-1]
    assert np.hypot(*f) > 0.1 * float(ds["mesh_force"].sel(mesh="stage3").values[-1])
