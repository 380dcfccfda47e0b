"""End-to-end CLI tests (typer runner, no subprocess)."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from geardyn.cli import app

runner = CliRunner()


def test_kinematics_json(examples_dir):
    res = runner.invoke(
        app,
        [
            "kinematics",
            str(examples_dir / "hammami_back_to_back.toml"),
            "--input",
            "motor=1498.5",
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    assert d["dof"] == 1
    assert d["meshes"][0]["mesh_hz"] == pytest.approx(320.667, abs=5e-4)


def test_kinematics_table_uses_config_inputs(examples_dir):
    res = runner.invoke(app, ["kinematics", str(examples_dir / "car_differential.toml")])
    assert res.exit_code == 0, res.output
    assert "DOF = 2" in res.output
    assert "cage" in res.output


def test_kinematics_bad_input_is_a_message(examples_dir):
    res = runner.invoke(
        app,
        ["kinematics", str(examples_dir / "car_differential.toml"), "--input", "left_wheel=100"],
    )
    assert res.exit_code == 2
    assert "degree(s) of freedom" in res.output
    assert "Traceback" not in res.output


def test_kinematics_bad_config_is_a_message(tmp_path):
    cfg = tmp_path / "bad.toml"
    cfg.write_text('frame = "f"\nlinks = ["f", "a"]\n')
    res = runner.invoke(app, ["kinematics", str(cfg), "--input", "a=10"])
    assert res.exit_code == 2
    assert "link 'a': has no turning pair" in res.output


def test_demo_runs_all_examples():
    res = runner.invoke(app, ["demo"])
    assert res.exit_code == 0, res.output
    for name in ("car_differential", "alouette3_mgb", "hammami_back_to_back", "reclaimer_drive"):
        assert name in res.output
    for step in ("geardyn stiffness", "geardyn modes", "geardyn transmission",
                 "geardyn diagnose"):
        assert step in res.output
    # the fault-to-verdict step ends with a localised alarm and the report's path
    assert "location: planetary.sun" in res.output and "alarms match" in res.output
    assert "report.html" in res.output


@pytest.mark.parametrize(
    ("command", "section"),
    [
        ("modes", "[planetary_dynamics]"),
        ("simulate", "[planetary_dynamics]"),
        ("transmission", "[transmission]"),
    ],
)
def test_missing_analysis_section_is_a_message(examples_dir, command, section):
    args = [command, str(examples_dir / "car_differential.toml")]
    if command == "simulate":
        args += ["--out", "unused.nc"]
    res = runner.invoke(app, args)
    assert res.exit_code == 2, res.output
    assert section in res.output  # brackets survive the terminal markup
    assert "Traceback" not in res.output
