"""CLI: version, the last-resort handler for unexpected errors, --debug (issue 13 item 1)."""

from __future__ import annotations

from typer.testing import CliRunner

import geardyn
from geardyn.cli import app
from geardyn.cli import common as cli_common

runner = CliRunner()


def test_version():
    r = runner.invoke(app, ["--version"])
    assert r.exit_code == 0 and r.output.strip() == f"geardyn {geardyn.__version__}"


def test_unexpected_error_is_one_line_and_debug_shows_it(monkeypatch, examples_dir):
    import geardyn.cli.kinematics as kin_cli

    def boom(*a, **k):
        raise RuntimeError("boom")

    monkeypatch.setattr(kin_cli, "analyze_kinematics", boom)
    monkeypatch.setitem(cli_common.DEBUG, "on", False)
    args = ["kinematics", str(examples_dir / "car_differential.toml")]
    r = runner.invoke(app, args)
    assert r.exit_code == 1
    assert "internal error: RuntimeError: boom" in r.output and "Traceback" not in r.output
    r = runner.invoke(app, ["--debug", *args])
    assert isinstance(r.exception, RuntimeError)
