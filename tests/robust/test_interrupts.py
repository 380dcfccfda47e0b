"""Issue 13: Ctrl-C, SIGKILL and resume of `geardyn simulate` (planetary Newmark) and
`geardyn transmission` (FE Verlet), in subprocesses.

One chain per model: (1) a run with --checkpoint-every is killed with SIGKILL once it has
written a checkpoint: no file at the final path; (2) --resume continues it and is stopped with
SIGINT: no crash (the FE run used to segfault), exit 130, the computed part written, readable,
with status 'interrupted', and every variable of it (steps before the kill and after the
resume) bit-identical to the same steps of an uninterrupted run of the config (in-process, same
API). Running a resumed run to its end is tested in-process (test_checkpoint.py).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from geardyn.config import load_config
from geardyn.run import run_simulation

ROOT = Path(__file__).resolve().parents[2]
EX = ROOT / "examples"
GEARDYN = [sys.executable, "-c", "from geardyn.cli import app; app(prog_name='geardyn')"]


def _start(args: list[str], cwd: Path) -> subprocess.Popen:
    env = {**os.environ, "COLUMNS": "120"}
    return subprocess.Popen(GEARDYN + args, cwd=cwd, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env=env)


def _wait_for_checkpoint(proc: subprocess.Popen, ckpt: Path, after_ns: int = 0,
                         timeout: float = 60.0) -> None:
    """Wait until ``ckpt`` is (re)written after ``after_ns`` (the loop is running)."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if ckpt.exists() and ckpt.stat().st_mtime_ns > after_ns:
            return
        if proc.poll() is not None:
            out = proc.stdout.read() if proc.stdout else ""
            pytest.fail(f"run ended (exit {proc.returncode}) before a checkpoint:\n{out}")
        time.sleep(0.02)
    proc.kill()
    pytest.fail("no checkpoint written")


def sigint_and_compare(proc: subprocess.Popen, out: Path, reference: xr.Dataset) -> int:
    """Ctrl-C ``proc``: exit 130 with the message and no traceback, the partial result at
    ``out`` has status ``interrupted`` and the same variables, its rows bit-identical to the
    beginning of the uninterrupted ``reference``. Returns the number of rows written."""
    proc.send_signal(signal.SIGINT)
    text, _ = proc.communicate(timeout=60)
    assert proc.returncode == 130, text
    assert "interrupted by SIGINT" in text and "Traceback" not in text, text
    with xr.open_dataset(out, engine="h5netcdf") as part:
        assert part.attrs["status"] == "interrupted"
        n = part.sizes["time"]
        assert 1 < n < reference.sizes["time"]
        # the computed part (before a kill and after a resume) is bit-identical to the
        # beginning of the uninterrupted run
        assert set(part.data_vars) == set(reference.data_vars)
        for name in reference.data_vars:
            assert np.array_equal(part[name].values, reference[name].isel(time=slice(0, n))
                                  .values, equal_nan=True), name
        assert np.array_equal(part["time"].values, reference["time"].values[:n])
    return n


def _chain(tmp_path: Path, command: list[str], out: Path, reference: xr.Dataset) -> None:
    ckpt = out.with_name(out.name + ".ckpt.npz")
    # (1) SIGKILL during the run
    p = _start(command + ["--checkpoint-every", "0.2"], tmp_path)
    _wait_for_checkpoint(p, ckpt)
    p.send_signal(signal.SIGKILL)
    p.wait(timeout=30)
    assert p.returncode == -signal.SIGKILL
    assert not out.exists(), "a killed run left a file at the final path"
    assert not list(tmp_path.glob(f".{out.name}*")), "no NetCDF write had begun"
    # (2) resume, then SIGINT (Ctrl-C)
    mtime = ckpt.stat().st_mtime_ns
    p = _start(command + ["--resume", "--checkpoint-every", "0.2"], tmp_path)
    _wait_for_checkpoint(p, ckpt, after_ns=mtime)
    sigint_and_compare(p, out, reference)
    assert ckpt.exists() and ckpt.stat().st_mtime_ns > mtime, "Ctrl-C writes a checkpoint"


def test_simulate_planetary_sigkill_sigint_resume(tmp_path: Path) -> None:
    text = (EX / "planetary_reclaimer.toml").read_text()
    # long enough (600,000 steps, ~1.5 s of CPU) for the SIGINT to arrive before the end
    text = text.replace("t_end_s = 0.05", "t_end_s = 60.0\nsave_every = 50")
    cfg_path = tmp_path / "reclaimer.toml"
    cfg_path.write_text(text)
    reference = run_simulation(load_config(cfg_path), seed=3)
    out = tmp_path / "run.nc"
    _chain(tmp_path, ["simulate", str(cfg_path), "--out", str(out), "--seed", "3"], out,
           reference)


def test_transmission_sigkill_sigint_resume(tmp_path: Path) -> None:
    text = (EX / "seed002_transmission.toml").read_text()
    text = text.replace("record_rate_hz = 50000.0", "record_rate_hz = 5000.0")
    cfg_path = tmp_path / "fe.toml"
    cfg_path.write_text(text)
    # 100 revolutions (~2-3 s of the default modal loop): the resumed run must still be
    # running when SIGINT comes
    reference = run_simulation(load_config(cfg_path), revolutions=100.0)
    out = tmp_path / "fe.nc"
    _chain(tmp_path, ["transmission", str(cfg_path), "--revolutions", "100", "--modes", "3",
                      "--netcdf", str(out)], out, reference)


WRITER = """
import sys
import numpy as np
import xarray as xr
from geardyn.results import to_netcdf
ds = xr.Dataset({"x": (("time", "c"), np.ones((1_000_000, 8)))}, attrs={"status": "ok"})
print("writing", flush=True)
to_netcdf(ds, sys.argv[1])
"""


def test_sigkill_while_writing_keeps_the_final_path_intact(tmp_path: Path) -> None:
    """Issue 13: SIGKILL while writing left an unreadable file at the final path. Now the
    file goes to a temporary name and is renamed: killed mid-write (64 MB), the previous file
    at the final path is untouched and readable."""
    out = tmp_path / "run.nc"
    xr.Dataset({"old": ("t", np.arange(3.0))}).to_netcdf(out, engine="h5netcdf")
    before = out.read_bytes()
    p = subprocess.Popen([sys.executable, "-c", WRITER, str(out)], stdout=subprocess.PIPE,
                         text=True)
    assert p.stdout is not None and p.stdout.readline().strip() == "writing"
    t0 = time.monotonic()
    tmp = []
    while time.monotonic() - t0 < 30 and p.poll() is None:
        tmp = [f for f in tmp_path.glob(".run.nc.*.tmp") if f.stat().st_size > 1_000_000]
        if tmp:
            break
        time.sleep(0.005)
    assert tmp, "the write went to a temporary file"
    p.send_signal(signal.SIGKILL)
    p.wait(timeout=30)
    assert out.read_bytes() == before
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert list(ds.data_vars) == ["old"]
