"""CLI of the FE transmission and divergence handling."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.config.loader import load_config, parse_config
from geardyn.models.transmission import SimulationDivergedError, simulate


def test_cli_modes_run_and_figures(examples_dir, tmp_path) -> None:
    cfg = examples_dir / "seed002_transmission.toml"
    r = CliRunner().invoke(app, ["transmission", str(cfg), "--modes-only", "--campbell",
                                 "0:2000:5 rpm"])
    assert r.exit_code == 0, r.output
    from tests.validation.independent import printed_mode_hz, rigid_axial_mode_hz  # first
    assert printed_mode_hz(r.output, 1) == pytest.approx(  # elastic mode: the output shaft
        rigid_axial_mode_hz(cfg), rel=5e-3)  # axial on its bearings, √(k/m) closed form
    assert "Campbell" in r.output
    out = tmp_path / "run.nc"
    r = CliRunner().invoke(app, ["transmission", str(cfg), "--revolutions", "2",
                                 "--out", str(out), "--plots", str(tmp_path)])
    assert r.exit_code == 0, r.output
    assert out.exists() and (tmp_path / "ias_spectrum_output.png").exists()
    assert "efficiency" in r.output


def test_cli_names_bad_field(tmp_path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text(
        'links = ["housing", "s"]\nframe = "housing"\n[transmission]\n'
        'drive = { at = { shaft = "s", node = 0 } }\n'
        'load = { at = { shaft = "s", node = 7 } }\n'
        '[[transmission.shafts]]\nname = "s"\nposition_m = [0, 0]\nlength_m = 0.5\n'
        "elements = 5\nouter_diameter_m = 0.05\n"
    )
    r = CliRunner().invoke(app, ["transmission", str(bad)])
    assert r.exit_code == 2
    assert "load.at.node" in r.output.replace("\n", "")


def test_divergence_stops_with_diagnosis_and_partial_result(examples_dir) -> None:
    d = load_config(examples_dir / "seed002_transmission.toml").model_dump(exclude_none=True)
    d["transmission"]["simulation"].update(integrator="explicit", time_step_s=5e-5)  # above
    # the explicit loop's stability limit
    with pytest.raises(SimulationDivergedError, match="diverged at t") as ei:
        simulate(parse_config(d), revolutions=1.0)
    res = ei.value.result
    assert res.time.size >= 1 and float(res.time[-1]) < 0.15
