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
        (["--baseline", "healthy.nc"], "--baseline and --record go together"),
        (["--seeds", "0,one"], "--seeds: expected comma-separated integers"),
        (["--k", "0"], "diagnosis.threshold_k"),
        (["--seeds", "0,0"], "diagnosis.baseline_seeds"),
        (["--seeds", "0,1", "--record-seed", "1"], "record_seed: 1 is also a baseline seed"),
        (["--baseline", "missing.nc", "--record", "missing.nc"], "file 'missing.nc' does not"),
        (["--baseline", "a.nc", "--record", "b.nc", "--seeds", "1"], "are for simulated runs"),
    ],
)
def test_bad_options_are_messages(tmp_path: Path, no_simulation, extra, message) -> None:
    res = runner.invoke(app, ["diagnose", CONFIG, "--out", str(tmp_path / "out"), *extra])
    assert res.exit_code == 2, res.output
    assert message in " ".join(res.output.split())


def test_output_dir_checked_before_any_work(tmp_path: Path, no_simulation) -> None:
    blocker = tmp_path / "file.txt"
    blocker.write_text("not a directory")
    res = runner.invoke(app, ["diagnose", CONFIG, "--out", str(blocker / "out")])
    assert res.exit_code == 2
    assert "cannot write to" in res.output
