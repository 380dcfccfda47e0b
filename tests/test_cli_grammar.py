"""One CLI grammar (issue 21): ``--out`` for outputs with old names as hidden aliases, one
range syntax for ``--campbell``, one overwrite policy (``--force``; an output folder written
whole or not at all), help text for every option."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np
import pytest
from typer.main import get_command
from typer.testing import CliRunner

from geardyn.cli import app

runner = CliRunner()


def test_every_option_and_argument_has_help():
    group = get_command(app)
    ctx = click.Context(group)
    missing = []
    for name in group.list_commands(ctx):
        for p in group.get_command(ctx, name).params:
            if getattr(p, "hidden", False):
                continue
            if not (getattr(p, "help", None) or "").strip():
                missing.append(f"{name} {'/'.join(getattr(p, 'opts', [p.name]))}")
    assert not missing, f"options without help text: {missing}"


def test_demo_help_names_every_source():
    r = runner.invoke(app, ["demo", "--help"], terminal_width=100)
    assert r.exit_code == 0
    text = " ".join(r.output.split())
    for source in ("Penaud", "Hammami 2015", "Wang 2010", "Thibault et al. 2024", "diagnose"):
        assert source in text, source


def test_transmission_out_campbell_and_deprecated_aliases(tmp_path):
    cfg = tmp_path / "t.toml"
    assert runner.invoke(app, ["init", "transmission", str(cfg)]).exit_code == 0
    r = runner.invoke(app, ["transmission", "--help"], terminal_width=120)
    assert "--out" in r.output and "--netcdf" not in r.output  # the old name is hidden
    r = runner.invoke(app, ["transmission", str(cfg), "--modes-only", "--modes", "3",
                            "--campbell", "0:2000:3 rpm"])
    assert r.exit_code == 0, r.output
    assert "Campbell" in r.output and "deprecated" not in r.output
    r = runner.invoke(app, ["transmission", str(cfg), "--modes-only", "--modes", "3",
                            "--campbell", "2000"])  # old form: top speed in rpm
    assert r.exit_code == 0, r.output
    assert "deprecated" in r.output and '"0:2000:5 rpm"' in r.output.replace("\n", "")
    r = runner.invoke(app, ["transmission", str(cfg), "--modes-only", "--campbell", "fast"])
    assert r.exit_code == 2 and "--campbell" in r.output
    out = tmp_path / "fe.nc"
    r = runner.invoke(app, ["transmission", str(cfg), "--revolutions", "0.05", "--netcdf",
                            str(out)])
    assert r.exit_code == 0, r.output
    assert "--netcdf is deprecated; use --out" in r.output and out.is_file()
    r = runner.invoke(app, ["transmission", str(cfg), "--revolutions", "0.05", "--out",
                            str(out)])
    assert r.exit_code == 2 and "--force" in r.output  # one overwrite policy
    r = runner.invoke(app, ["transmission", str(cfg), "--out", str(out), "--netcdf",
                            str(out)])
    assert r.exit_code == 2 and "give only --out" in r.output


def test_stiffness_out_alias_and_one_pair(examples_dir, tmp_path):
    cfg = str(examples_dir / "seed002_two_stage.toml")
    out = tmp_path / "k.nc"
    r = runner.invoke(app, ["stiffness", cfg, "--samples", "16", "--out", str(out)])
    assert r.exit_code == 2 and "--pair" in r.output  # one file cannot hold two pairs' tables
    r = runner.invoke(app, ["stiffness", cfg, "--pair", "low", "--samples", "16", "--netcdf",
                            str(out)])
    assert r.exit_code == 0 and "deprecated" in r.output and out.is_file(), r.output
    r = runner.invoke(app, ["stiffness", cfg, "--pair", "low", "--samples", "16", "--out",
                            str(out)])
    assert r.exit_code == 2 and "--force" in r.output
    r = runner.invoke(app, ["stiffness", cfg, "--pair", "low", "--samples", "16", "--out",
                            str(out), "--force"])
    assert r.exit_code == 0, r.output


def test_analyze_writes_its_folder_whole_and_only_with_force(examples_dir, tmp_path):
    fs = 10_000.0
    t = np.arange(0.0, 4.0, 1.0 / fs)
    x = np.sin(2 * np.pi * 320.667 * t)  # the bench's sun-planet mesh frequency at 1498.5 rpm
    sig = tmp_path / "s.npy"
    np.save(sig, x)
    rep = tmp_path / "rep"
    args = ["analyze", str(sig), "--fs", "10000", "--config",
            str(examples_dir / "hammami_back_to_back.toml"), "--speed", "motor=1498.5",
            "--out", str(rep)]
    r = runner.invoke(app, args)
    assert r.exit_code == 0, r.output
    written = sorted(p.name for p in rep.iterdir())
    assert "order_spectrum.png" in written and "indicators.csv" in written
    (rep / "tsa_old_shaft.png").write_bytes(b"stale figure of an earlier run")
    r = runner.invoke(app, args)
    assert r.exit_code == 2 and "--force" in r.output
    assert (rep / "tsa_old_shaft.png").exists()  # refused: nothing touched
    r = runner.invoke(app, [*args, "--force"])
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in rep.iterdir()) == written  # no stale file
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".rep.")]  # no leftovers
    (rep / "notes.toml").write_text("x = 1")  # not a report file: --force does not delete it
    r = runner.invoke(app, [*args, "--force"])
    assert r.exit_code == 2 and "notes.toml" in r.output
    assert (rep / "notes.toml").exists()


def test_force_never_replaces_the_working_folder(tmp_path, monkeypatch):
    from geardyn.cli.common import check_report_dir
    from geardyn.errors import InputError

    monkeypatch.chdir(tmp_path)
    (tmp_path / "old.png").write_bytes(b"figure")
    with pytest.raises(InputError, match="working folder"):
        check_report_dir(Path("."), "--out", force=True)


def test_analyze_interrupted_keeps_the_earlier_folder(examples_dir, tmp_path, monkeypatch):
    """A failure while writing leaves the earlier folder as it was and no partial folder."""
    from geardyn.cli.common import report_folder

    rep = tmp_path / "rep"
    rep.mkdir()
    (rep / "old.png").write_bytes(b"earlier")
    with pytest.raises(KeyboardInterrupt), report_folder(rep) as folder:
        (folder / "new.png").write_bytes(b"new")
        raise KeyboardInterrupt
    assert [p.name for p in rep.iterdir()] == ["old.png"]
    assert [p.name for p in tmp_path.iterdir()] == ["rep"]
    with report_folder(rep) as folder:
        (folder / "new.png").write_bytes(b"new")
    assert [p.name for p in rep.iterdir()] == ["new.png"]
    assert [p.name for p in tmp_path.iterdir()] == ["rep"]


def test_diagnose_folder_is_replaced_only_with_force(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert runner.invoke(app, ["init", "planetary"]).exit_code == 0
    args = ["diagnose", "planetary.toml", "--out", "diag", "--seeds", "0,1", "--t-end", "0.6",
            "--skip", "0.1", "--blocks", "2"]
    r = runner.invoke(app, args)
    assert r.exit_code == 0, r.output
    (tmp_path / "diag" / "old_figure.png").write_bytes(b"stale")
    r = runner.invoke(app, args)
    assert r.exit_code == 2 and "--force" in r.output
    r = runner.invoke(app, [*args, "--force"])
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in (tmp_path / "diag").iterdir()) == ["report.html",
                                                                     "verdict.json"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["diag", "planetary.toml"]
