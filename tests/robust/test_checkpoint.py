"""Issue 13: exact chunking, stop/resume in-process, checkpoint files, atomic writes, output
path checks (fast; the subprocess Ctrl-C/SIGKILL tests are in test_interrupts.py)."""

from __future__ import annotations

import os

import numpy as np
import pytest
from typer.testing import CliRunner

from geardyn.checkpoint import (
    check_output,
    checkpoint_path,
    load_checkpoint,
    run_hash,
    save_checkpoint,
    write_atomic,
)
from geardyn.cli import app
from geardyn.config import load_config
from geardyn.errors import InputError
from geardyn.models.planetary.build import prepare
from geardyn.solve.control import RunControl
from geardyn.solve.integrate import newmark


@pytest.fixture(scope="module")
def lin_parker_prep(examples_dir):
    return prepare(load_config(examples_dir / "planetary_lin_parker.toml"))


def _fields(res):
    return (res.t, res.q, res.v, res.k, res.delta)


def test_newmark_chunking_is_exact(lin_parker_prep):
    """The same run in one chunk, in chunks of 97 steps and in chunks sized by RunControl
    gives the same bytes (states, saved rows, energy terms)."""
    p = lin_parker_prep
    one = newmark(p.system, p.q0, p.v0, 0.01, 2e-5, save_every=3, chunk_steps=10**9)
    small = newmark(p.system, p.q0, p.v0, 0.01, 2e-5, save_every=3, chunk_steps=97)
    ctl = newmark(p.system, p.q0, p.v0, 0.01, 2e-5, save_every=3,
                  control=RunControl(chunk_wall_s=1e-4))
    for other in (small, ctl):
        assert all(np.array_equal(a, b) for a, b in zip(_fields(one), _fields(other),
                                                         strict=True))
        assert other.energy == one.energy
    assert one.t.size == 500 // 3 + 1


def _stop_after_first_chunk() -> tuple[RunControl, list[dict]]:
    saved: list[dict] = []

    def progress(_f: float) -> None:
        ctl.request_stop("test stop")

    ctl = RunControl(progress=progress, checkpoint=lambda s: saved.append(
        {k: np.array(v, copy=True) if isinstance(v, np.ndarray) else v for k, v in s.items()}))
    return ctl, saved


def test_newmark_stop_and_resume_bit_identical(lin_parker_prep, tmp_path):
    """A stop request ends the run after its chunk with status 'interrupted' and the computed
    part; its checkpoint (through an .npz file) resumes to the uninterrupted result."""
    p = lin_parker_prep
    full = newmark(p.system, p.q0, p.v0, 0.01, 2e-5, save_every=2)
    ctl, saved = _stop_after_first_chunk()
    part = newmark(p.system, p.q0, p.v0, 0.01, 2e-5, save_every=2, control=ctl)
    assert part.status == "interrupted" and "test stop" in part.diagnosis
    n = part.t.size
    assert 1 < n < full.t.size
    assert np.array_equal(part.q, full.q[:n])
    f = tmp_path / "state.npz"
    save_checkpoint(f, saved[-1], "abc")
    state = load_checkpoint(f, "abc")
    res = newmark(p.system, p.q0, p.v0, 0.01, 2e-5, save_every=2,
                  control=RunControl(resume=state))
    assert res.status == "ok"
    assert all(np.array_equal(a, b) for a, b in zip(_fields(full), _fields(res), strict=True))
    assert res.energy == full.energy
    with pytest.raises(InputError, match="another run"):  # other step: refused
        newmark(p.system, p.q0, p.v0, 0.01, 1e-5, save_every=2,
                control=RunControl(resume=state))


def test_transmission_stop_and_resume_bit_identical(examples_dir):
    from geardyn.models.transmission import build_model, prepare, simulate

    cfg = load_config(examples_dir / "seed002_transmission.toml")
    prep = prepare(build_model(cfg), cfg.transmission.speed_law.reference.shaft)
    full = simulate(cfg, revolutions=0.3, prepared=prep)
    ctl, saved = _stop_after_first_chunk()
    part = simulate(cfg, revolutions=0.3, prepared=prep, control=ctl)
    assert part.attrs["status"] == "interrupted"
    n = part.sizes["time"]
    assert 1 < n < full.sizes["time"]
    assert np.array_equal(part["mesh_force"].values, full["mesh_force"].values[:n])
    res = simulate(cfg, revolutions=0.3, prepared=prep, control=RunControl(resume=saved[-1]))
    assert res.attrs["status"] == "ok"
    for name in full.data_vars:
        assert np.array_equal(res[name].values, full[name].values), name
    for key in ("energy_input_J", "energy_output_J", "energy_gear_friction_J", "steps"):
        assert res.attrs[key] == full.attrs[key]


def test_checkpoint_of_another_config_refused(tmp_path, examples_dir):
    cfg = load_config(examples_dir / "planetary_lin_parker.toml")
    digest = run_hash(cfg, seed=0, t_end_s=None)
    assert digest == run_hash(cfg, seed=0, t_end_s=None)
    assert digest != run_hash(cfg, seed=1, t_end_s=None)
    f = tmp_path / "x.ckpt.npz"
    save_checkpoint(f, {"step": 3, "q": np.arange(3.0)}, digest)
    assert load_checkpoint(f, digest)["step"] == 3
    with pytest.raises(InputError, match="another config or other options"):
        load_checkpoint(f, run_hash(cfg, seed=1, t_end_s=None))
    f.write_bytes(b"not a zip")
    with pytest.raises(InputError, match="unreadable"):
        load_checkpoint(f, digest)
    with pytest.raises(InputError, match="no checkpoint"):
        load_checkpoint(tmp_path / "missing.npz", digest)


def test_write_atomic_never_leaves_a_partial_file(tmp_path):
    target = tmp_path / "run.nc"

    def broken(tmp):
        tmp.write_bytes(b"half")
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        write_atomic(target, broken)
    assert not target.exists()
    target.write_bytes(b"old result")
    with pytest.raises(OSError):
        write_atomic(target, broken)
    assert target.read_bytes() == b"old result"
    write_atomic(target, lambda tmp: tmp.write_bytes(b"new"))
    assert target.read_bytes() == b"new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]  # no temporary left


def test_check_output(tmp_path):
    with pytest.raises(InputError, match="--out: directory .* does not exist"):
        check_output(tmp_path / "nope" / "run.nc", "--out")
    (tmp_path / "d").mkdir()
    with pytest.raises(InputError, match="is a directory"):
        check_output(tmp_path / "d", "--out")
    f = tmp_path / "run.nc"
    f.write_bytes(b"x")
    with pytest.raises(InputError, match="exists; pass --force"):
        check_output(f, "--out")
    assert check_output(f, "--out", overwrite=True) == f
    if os.geteuid() != 0:  # root may write anywhere
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        with pytest.raises(InputError, match="not writable"):
            check_output(ro / "run.nc", "--out")


def test_cli_output_rules_and_checkpoint_cleanup(tmp_path, examples_dir):
    """--out into a missing directory fails before the run; an existing file is kept unless
    --force; a finished run with --checkpoint-every removes its checkpoint; --resume without a
    checkpoint, or with other options, is refused (exit 2)."""
    cfg = str(examples_dir / "planetary_lin_parker.toml")
    run = CliRunner().invoke
    r = run(app, ["simulate", cfg, "--out", str(tmp_path / "no" / "run.nc")])
    assert r.exit_code == 2 and "does not exist" in r.output
    out = tmp_path / "run.nc"
    out.write_bytes(b"precious")
    r = run(app, ["simulate", cfg, "--out", str(out)])
    assert r.exit_code == 2 and "pass --force" in r.output
    assert out.read_bytes() == b"precious"
    r = run(app, ["simulate", cfg, "--out", str(out), "--force", "--checkpoint-every", "1e-6"])
    assert r.exit_code == 0, r.output
    assert not checkpoint_path(out).exists()
    r = run(app, ["simulate", cfg, "--out", str(out), "--resume"])
    assert r.exit_code == 2 and "no checkpoint" in r.output
    save_checkpoint(checkpoint_path(out), {"step": 1},
                    run_hash(load_config(cfg), seed=0, t_end_s=None, revolutions=None))
    r = run(app, ["simulate", cfg, "--out", str(out), "--resume", "--seed", "2"])
    assert r.exit_code == 2 and "another config or other options" in r.output
    r = run(app, ["simulate", cfg, "--out", str(out), "--force", "--checkpoint-every", "-1"])
    assert r.exit_code == 2 and "--checkpoint-every" in r.output


def test_long_run_estimated_before_it_goes_on(lin_parker_prep):
    """Issue 13: t_end_s = 1e4 ran for hours without a word. After two short chunks (the
    first loads the compiled code) the run announces steps × measured cost per step; here the
    run is stopped right after the estimate. 5e8 steps at 1-1000 µs each: 500 s to 5e5 s."""
    p = lin_parker_prep
    est: list[float] = []

    def progress(_f: float) -> None:
        if est:
            ctl.request_stop()

    ctl = RunControl(estimate=est.append, progress=progress)
    res = newmark(p.system, p.q0, p.v0, 1e4, 2e-5, save_every=10**6, control=ctl)
    assert res.status == "interrupted" and len(est) == 1
    assert 500.0 < est[0] < 5e5
    # records of 5e8 samples (over 100 GB) are refused before the run
    with pytest.raises(InputError, match=r"500,000,001 samples × \d+ values .* raise "
                       r"save_every \(1\)"):
        newmark(p.system, p.q0, p.v0, 1e4, 2e-5)
