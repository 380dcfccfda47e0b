"""`geardyn simulate` runs the FE transmission (seed 002); `geardyn transmission` is its alias
(the same run); a config describing a lumped model and an FE transmission needs --model;
Ctrl-C and --resume work through `simulate` (and across the alias: same checkpoint)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.config import load_config
from geardyn.errors import ConfigError, InputError
from geardyn.run import run_simulation, simulated_model
from tests.robust.test_interrupts import _start, _wait_for_checkpoint, sigint_and_compare

ROOT = Path(__file__).resolve().parents[2]
EX = ROOT / "examples"
runner = CliRunner()

#: A [dynamics] model of the seed 002 mechanism beside its [transmission] (two models).
DYNAMICS = """
[dynamics]
module_m = 0.003
face_width_m = 0.03

[dynamics.simulation]
t_end_s = 0.005
dt_s = 1e-5
initial_speed_rpm = { input = 1000.0 }
"""


def test_simulate_and_transmission_alias_give_identical_datasets(tmp_path) -> None:
    """The same FE run (1 revolution of the seed 002 example) written by `simulate` and by
    its alias `transmission`: every variable, coordinate and attribute equal (wall-clock
    times aside)."""
    cfg = EX / "seed002_transmission.toml"
    a, b = tmp_path / "simulate.nc", tmp_path / "transmission.nc"
    r = runner.invoke(app, ["simulate", str(cfg), "--out", str(a), "--revolutions", "1"])
    assert r.exit_code == 0, r.output
    assert "efficiency" in r.output  # the FE summary of `transmission`
    r = runner.invoke(app, ["transmission", str(cfg), "--netcdf", str(b), "--revolutions", "1",
                            "--modes", "2"])
    assert r.exit_code == 0, r.output
    with xr.open_dataset(a, engine="h5netcdf") as da, xr.open_dataset(b, engine="h5netcdf") as db:
        assert da.attrs["model"] == "transmission"
        xr.testing.assert_identical(da.drop_attrs(deep=False).load(),
                                    db.drop_attrs(deep=False).load())
        keep = {k for k in da.attrs if not k.startswith("wall_")}
        assert keep == {k for k in db.attrs if not k.startswith("wall_")}
        for k in keep:
            assert np.array_equal(np.asarray(da.attrs[k]), np.asarray(db.attrs[k])), k
    assert "alias" in runner.invoke(app, ["transmission", "--help"]).output.lower()


def test_lumped_and_fe_models_together_need_model(tmp_path) -> None:
    """[dynamics] + [transmission]: simulate and modes ask for --model (naming both models);
    --model picks one; a model the config lacks is refused naming its section."""
    path = tmp_path / "both.toml"
    path.write_text((EX / "seed002_transmission.toml").read_text() + DYNAMICS)
    cfg = load_config(path)
    with pytest.raises(ConfigError, match=r"--model mechanism \| transmission"):
        simulated_model(cfg)
    assert simulated_model(cfg, "transmission") == "transmission"
    assert simulated_model(cfg, "mechanism") == "mechanism"
    with pytest.raises(ConfigError, match=r"model 'planetary'.*\[planetary_dynamics\]"):
        simulated_model(cfg, "planetary")
    with pytest.raises(InputError, match="model: must be one of"):
        simulated_model(cfg, "fe")
    out = tmp_path / "run.nc"
    for cmd in (["simulate", str(path), "--out", str(out)], ["modes", str(path)]):
        r = runner.invoke(app, cmd, env={"COLUMNS": "200"})
        assert r.exit_code == 2 and "--model mechanism | transmission" in r.output, r.output
    r = runner.invoke(app, ["simulate", str(path), "--out", str(out), "--model", "mechanism"])
    assert r.exit_code in (0, 3), r.output  # the torsional model ran (no load: may be suspect)
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds.attrs["model"] != "transmission"
    r = runner.invoke(app, ["modes", str(path), "--model", "transmission", "--max-hz", "100"])
    assert r.exit_code == 0 and "FE shaft lines" in r.output, r.output


def test_simulate_fe_sigint_and_resume_through_the_alias(tmp_path) -> None:
    """`simulate` of the FE model with checkpoints stopped by SIGINT (exit 130, the computed
    part written with status interrupted and bit-identical to an uninterrupted run), then
    resumed by `transmission --resume` (the same run, hence the same checkpoint) and stopped
    again: the longer part is still bit-identical."""
    text = (EX / "seed002_transmission.toml").read_text()
    text = text.replace("record_rate_hz = 50000.0", "record_rate_hz = 5000.0")
    cfg_path = tmp_path / "fe.toml"
    cfg_path.write_text(text)
    # 100 revolutions (~2-3 s of the default modal loop): still running when SIGINT comes
    reference = run_simulation(load_config(cfg_path), revolutions=100.0)
    out = tmp_path / "fe.nc"
    ckpt = out.with_name(out.name + ".ckpt.npz")
    sizes = []
    for command in (["simulate", str(cfg_path), "--out", str(out)],
                    ["transmission", str(cfg_path), "--netcdf", str(out), "--modes", "1",
                     "--resume"]):
        mtime = ckpt.stat().st_mtime_ns if ckpt.exists() else 0
        p = _start(command + ["--revolutions", "100", "--checkpoint-every", "0.2"], tmp_path)
        _wait_for_checkpoint(p, ckpt, after_ns=mtime)
        n = sigint_and_compare(p, out, reference)
        sizes.append(n)
    assert sizes[1] > sizes[0]
