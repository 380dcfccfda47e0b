"""``geardyn diagnose``: errors are messages with exit code 2 (before any simulation runs)."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from geardyn.cli import app
from tests.conftest import EXAMPLES

runner = CliRunner()
CONFIG = str(EXAMPLES / "planetary_reclaimer.toml")


@pytest.fixture
def no_simulation(monkeypatch: pytest.MonkeyPatch) -> None:
    """Fail the test if a simulation starts (errors must come first)."""

    def boom(*args, **kwargs):
        raise AssertionError("a simulation ran before the input error")

    monkeypatch.setattr("geardyn.run.run_simulation", boom)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--baseline", "healthy.nc"], "--baseline needs --record"),
        (["--seeds", "0,one"], "--seeds: expected comma-separated integers"),
        # issue 20: the option typed is named (then the [diagnosis] field it overrides)
        (["--k", "0"], "'--k': must be > 0"),
        (["--k", "inf"], "'--k': must be a finite number"),
        (["--skip", "nan"], "'--skip': must be a finite number"),
        (["--seeds", "0,0"], "--seeds (diagnosis.baseline_seeds)"),
        (["--seeds", "0,1", "--record-seed", "1"], "--record-seed: 1 is also a baseline seed"),
        (["--baseline", "missing.nc", "--record", "missing.nc"], "file 'missing.nc' does not"),
        (["--baseline", "a.nc", "--record", "b.nc", "--seeds", "1"], "are for simulated runs"),
        (["--revolutions", "4"], "diagnosis.revolutions (--revolutions): applies to the FE"),
    ],
)
def test_bad_options_are_messages(tmp_path: Path, no_simulation, extra, message) -> None:
    res = runner.invoke(app, ["diagnose", CONFIG, "--out", str(tmp_path / "out"), *extra])
    assert res.exit_code == 2, res.output
    assert message in " ".join(res.output.split())


def test_output_dir_checked_before_any_work(tmp_path: Path, no_simulation) -> None:
    blocker = tmp_path / "file.txt"
    blocker.write_text("not a directory")
    config = tmp_path / "reclaimer.toml"  # with sensors (a config without is refused first)
    config.write_text((EXAMPLES / "planetary_reclaimer.toml").read_text() + SENSORS)
    res = runner.invoke(app, ["diagnose", str(config), "--out", str(blocker / "out")])
    assert res.exit_code == 2
    assert "cannot write to" in res.output


SENSORS = """
[[sensors]]
name = "acc_ring"
kind = "accelerometer"
location = "ring"
stage = "planetary"
shaft = "sun"
sample_rate_hz = 2000.0
noise_rms = 1.0
"""


def test_diagnose_short_run_end_to_end(tmp_path: Path) -> None:
    """Seed 004 reclaimer (sun crack) with a ring accelerometer, 3 s runs, reference residuals:
    exit 0, verdict table printed, verdict.json with every component and its state, one
    report.html."""
    import json

    config = tmp_path / "reclaimer.toml"
    config.write_text((EXAMPLES / "planetary_reclaimer.toml").read_text() + SENSORS)
    out = tmp_path / "diag"
    res = runner.invoke(app, ["diagnose", str(config), "--out", str(out), "--t-end", "3",
                              "--skip", "0.5", "--seeds", "0,1", "--blocks", "2",
                              "--residuals"])
    assert res.exit_code == 0, res.output
    text = " ".join(res.output.split())
    assert "planetary.sun" in text and "worst indicator" in text
    assert f"report {out / 'report.html'}" in text
    d = json.loads((out / "verdict.json").read_text())
    assert d["baseline"]["seeds"] == [0, 1] and d["record"]["seed"] == 100
    assert d["channels"] == ["acc_ring"]
    assert [f["component"] for f in d["expected_faults"]] == ["planetary.sun"]
    assert "planetary.sun" in d["components"]
    assert any(k.startswith("RR_") for c in d["components"].values() for k in c["indicators"])
    for c in d["components"].values():
        assert c["state"] in ("healthy", "alarm", "uncertain", "unknown")
        assert c["state"] != "healthy" or c["indicators"]
    assert sorted(p.name for p in out.iterdir()) == ["report.html", "verdict.json"]
    assert (out / "report.html").read_text().count("data:image/png;base64,") >= 4


def test_diagnose_result_files(tmp_path: Path) -> None:
    """--baseline/--record NetCDF result files (written by geardyn.results.to_netcdf): verdict
    without simulation; the record's faults are unknown (expected_faults null)."""
    import json

    import geardyn
    from geardyn.diagnosis.faults import healthy_variant
    from geardyn.results import to_netcdf
    from geardyn.run import run_simulation

    config = tmp_path / "reclaimer.toml"
    config.write_text((EXAMPLES / "planetary_reclaimer.toml").read_text() + SENSORS)
    cfg = geardyn.load_config(config)
    files = []
    for name, c, seed in (("h0", healthy_variant(cfg), 0), ("h1", healthy_variant(cfg), 1),
                          ("rec", cfg, 100)):
        files.append(tmp_path / f"{name}.nc")
        to_netcdf(run_simulation(c, seed=seed, t_end_s=3.0), files[-1])
    out = tmp_path / "diag"
    res = runner.invoke(app, ["diagnose", str(config), "--out", str(out), "--baseline",
                              str(files[0]), "--baseline", str(files[1]), "--record",
                              str(files[2]), "--skip", "0.5", "--blocks", "2"])
    assert res.exit_code == 0, res.output
    d = json.loads((out / "verdict.json").read_text())
    assert d["baseline"]["files"] == [str(files[0]), str(files[1])]
    assert d["record"] == {"file": str(files[2])}
    assert d["expected_faults"] is None and "localised" not in d["summary"]
    assert (out / "report.html").is_file()
