"""CLI: ``geardyn modes`` and ``geardyn simulate``."""

from __future__ import annotations

import xarray as xr
from typer.testing import CliRunner

from geardyn.cli import app

from .conftest import EX

runner = CliRunner()


def test_modes_cli_table_plot_netcdf(tmp_path):
    png, nc = tmp_path / "m.png", tmp_path / "m.nc"
    r = runner.invoke(app, ["modes", str(EX / "planetary_bench_36dof.toml"), "--plot", str(png),
                            "--netcdf", str(nc)])
    assert r.exit_code == 0, r.output
    assert "1847.1" in r.output and "1888.0" in r.output and "translational" in r.output
    assert png.stat().st_size > 1000
    ds = xr.open_dataset(nc, engine="h5netcdf")
    assert ds.sizes["mode"] == 36 and ds.frequency.attrs["units"] == "Hz"


def test_modes_cli_torsional_override():
    r = runner.invoke(app, ["modes", str(EX / "planetary_bench_36dof.toml"), "--reduction",
                            "torsional"])
    assert r.exit_code == 0, r.output
    assert "12 DOF" in r.output


def test_simulate_cli_writes_netcdf(tmp_path):
    out = tmp_path / "run.nc"
    r = runner.invoke(app, ["simulate", str(EX / "planetary_lin_parker.toml"), "--out", str(out),
                            "--t-end", "0.002"])
    assert r.exit_code == 0, r.output
    ds = xr.open_dataset(out, engine="h5netcdf")
    assert "planet2.u" in ds.dof.values and "lsr_stage" in ds
    assert ds.time.attrs["units"] == "s"


def test_cli_bad_config_is_a_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text((EX / "planetary_lin_parker.toml").read_text().replace(
        "planet_bearing_n_per_m = 1e8", "planet_bearing_n_per_m = -1e8"))
    r = runner.invoke(app, ["modes", str(bad)])
    assert r.exit_code == 2
    assert "planet_bearing_n_per_m" in r.output
