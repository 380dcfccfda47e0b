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
