"""Sweep store integrity (issue 20 part 1): every sample of every case stored whatever the
order cases finish in, one driver per store, damaged chunks found and re-run, kill -9 of the
driver and of a worker at random moments, non-zero exit on failed cases, failed cases not
re-run unless asked. Small cases: the seed 004 gearbox for 2 s."""

from __future__ import annotations

import contextlib
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from geardyn.sweep import load_spec, open_dataset, run
from geardyn.sweep.runner import _client
from geardyn.sweep.store import statuses, verify

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / "examples" / "seed004_diagnose_sun_crack.toml"
GEARDYN = str(Path(sys.executable).parent / "geardyn")

# a speed axis (five paths zipped, as the example data set) and the carrier encoder: the
# faster case has more encoder samples than the slower one
SPEC = f"""
[sweep]
base = "{BASE}"
seed = 5

[run]
t_end_s = 2.0

[[axes]]
name = "motor_speed_rpm"
path = "planetary_dynamics.simulation.initial_speed_rpm.motor"
group = "speed"
values = [1187.5, 950.0]

[[axes]]
name = "rated"
path = "planetary_dynamics.simulation.motor.rated_speed_rpm"
group = "speed"
values = [1187.5, 950.0]

[[axes]]
name = "supply"
path = "planetary_dynamics.simulation.motor.frequency_hz"
group = "speed"
values = [62.5, 50.0]

[[axes]]
name = "sun0"
path = "planetary_dynamics.simulation.initial_speed_rpm.sun"
group = "speed"
values = [40.5329, 32.4263]

[[axes]]
name = "sun_in"
path = "input_speeds_rpm.sun"
group = "speed"
values = [40.5329, 32.4263]

[[axes]]
name = "crack"
path = "planetary_dynamics.stages[0].faults[0].crack_fraction"
values = [0.0, 0.3]

[outputs.channels]
names = ["carrier_enc", "ring_acc"]
every = 8
samples = 4000

[outputs.indicators]
enabled = false
"""


@pytest.fixture(scope="module")
def spec_path(tmp_path_factory: pytest.TempPathFactory) -> Path:
    p = tmp_path_factory.mktemp("spec") / "speed.toml"
    p.write_text(SPEC)
    return p


@pytest.fixture(scope="module")
def cluster():  # noqa: ANN201 - distributed.Client
    with _client(None, 2) as client:
        client.wait_for_workers(2, timeout=120)
        yield client


@pytest.fixture(scope="module")
def reference(spec_path: Path, tmp_path_factory: pytest.TempPathFactory, cluster) -> Path:  # noqa: ANN001
    """The sweep on ONE in-process worker, uninterrupted."""
    from distributed import Client

    out = tmp_path_factory.mktemp("ref") / "ref.zarr"
    with Client(processes=False, n_workers=1, threads_per_worker=1,
                dashboard_address=":0") as client:
        assert run(spec_path, out, client=client).run == 4
    return out


def same_store(a: Path, b: Path) -> None:
    x, y = open_dataset(a).load(), open_dataset(b).load()
    assert sorted(x.variables) == sorted(y.variables)
    assert x.attrs == y.attrs
    for name in x.variables:
        if name != "wall_time_s":
            assert x[name].dims == y[name].dims, name
            np.testing.assert_array_equal(x[name].values, y[name].values, err_msg=name)


def test_every_sample_of_every_case(reference: Path, spec_path: Path) -> None:
    """The faster case keeps all its encoder samples (the store is sized from the spec, not
    from the case written first); the stored row equals the channel of a direct run."""
    from geardyn.config.loader import parse_config
    from geardyn.results import channel
    from geardyn.run import run_simulation
    from geardyn.sweep.case import _decimated

    ds = open_dataset(reference).load()
    assert list(ds["status"].values) == ["ok"] * 4
    assert list(ds["message"].values) == [""] * 4
    n = ds["channels.carrier_enc.length"].values.astype(int)
    assert n[0] > n[2] > 0  # 1187.5 rpm cases have more encoder samples than 950 rpm ones
    np.testing.assert_array_equal(n, ds["channels.carrier_enc.samples_computed"].values)
    assert ds["channels.carrier_enc"].sizes["carrier_enc.sample"] == 4000
    assert ds["channels.carrier_enc.length"].attrs["units"] == "1"
    sw = load_spec(spec_path)
    case = sw.cases[1]  # fast, cracked
    res = run_simulation(parse_config(sw.case_config(case)), seed=case.seed, t_end_s=2.0)
    ch = channel(res, "carrier_enc")
    values, t = _decimated(ch.values, ch.time, 8, ch.sampling)
    assert values.size == n[1]
    np.testing.assert_array_equal(ds["channels.carrier_enc"].values[1, :n[1]], values)
    np.testing.assert_array_equal(ds["channels.carrier_enc.time"].values[1, :n[1]], t)
    assert np.isnan(ds["channels.carrier_enc"].values[1, n[1]:]).all()


def test_one_and_two_workers_give_one_store(reference: Path, spec_path: Path,
                                                         cluster, tmp_path: Path) -> None:  # noqa: ANN001
    """(Repeated runs: every other test of this file compares its store with the reference
    too — after damage, two drivers, kills.)"""
    run(spec_path, tmp_path / "two.zarr", client=cluster)
    same_store(reference, tmp_path / "two.zarr")


def _chunk(store: Path, name: str, case: int) -> Path:
    files = sorted((store / name / "c").glob(f"{case}/**/*"))
    files = [f for f in files if f.is_file()] or sorted((store / name / "c").glob(f"{case}"))
    assert files, f"no chunk file of {name} case {case}"
    return files[0]


def test_damaged_chunks_named_and_rerun(reference: Path, spec_path: Path, cluster,  # noqa: ANN001
                                        tmp_path: Path) -> None:
    import shutil

    from typer.testing import CliRunner

    from geardyn.cli import app

    out = tmp_path / "damaged.zarr"
    shutil.copytree(reference, out)
    assert verify(out) == {}
    _chunk(out, "channels.carrier_enc", 1).unlink()  # a deleted chunk reads as NaN
    _chunk(out, "channels.ring_acc.time", 3).write_bytes(os.urandom(200))  # garbage
    damaged = verify(out)
    assert sorted(damaged) == [1, 3], damaged
    assert "checksum" in damaged[1] and "unreadable" in damaged[3]
    r = CliRunner().invoke(app, ["sweep", str(spec_path), "--out", str(out), "--verify"])
    assert r.exit_code == 1, r.output
    assert "case 1:" in r.output and "case 3:" in r.output and "2 of 4" in r.output
    summary = run(spec_path, out, client=cluster)
    assert sorted(summary.damaged) == [1, 3] and summary.run == 2
    same_store(reference, out)
    assert verify(out) == {}


def test_a_second_driver_is_refused(reference: Path, spec_path: Path, cluster,  # noqa: ANN001
                                    tmp_path: Path) -> None:
    """Two drivers started at the same moment on one --out: one runs every case once, the
    other is refused naming it (pid, host, start time); no internal error. A stale lock
    (a dead pid on this host) is taken over with a warning."""
    import json
    import socket

    from geardyn.sweep.lock import lock_path

    out = tmp_path / "race.zarr"
    cmd = [GEARDYN, "sweep", str(spec_path), "--out", str(out), "--scheduler",
           cluster.scheduler.address]
    procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for _ in range(2)]
    outs = [p.communicate(timeout=240) for p in procs]
    text = "\n".join(o + e for o, e in outs)
    assert "Traceback" not in text and "internal error" not in text.lower(), text
    run_now = []
    for p, (o, e) in zip(procs, outs, strict=True):
        if p.returncode == 2:  # refused before computing anything, naming the running one
            assert "in use by another geardyn sweep" in o + e and "pid " in o + e, o + e
            run_now.append(0)
        else:  # (a driver that got the lock after the other one finished runs nothing)
            assert p.returncode == 0, o + e
            run_now.append(int(o.replace("\n", " ").split(" case(s) run now")[0].split()[-1]))
    assert sorted(run_now) == [0, 4], text  # every case computed exactly once
    same_store(reference, out)
    assert not lock_path(out).exists()
    # a stale lock: this host, a pid that is not running
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    lock_path(out).write_text(json.dumps({"pid": dead.pid, "host": socket.gethostname(),
                                          "started": "earlier"}))
    with pytest.warns(UserWarning, match="taking over the lock"):
        run(spec_path, out, client=cluster)
    lock_path(out).write_text(json.dumps({"pid": os.getpid(), "host": socket.gethostname()}))
    from geardyn.errors import InputError

    with pytest.raises(InputError, match=f"pid {os.getpid()}"):
        run(spec_path, out, client=cluster)
    lock_path(out).unlink()


def _stored(out: Path) -> int:
    return int((statuses(out) != "").sum()) if out.exists() else 0


def test_chaos_kills_driver_and_worker(reference: Path, spec_path: Path, cluster,  # noqa: ANN001
                                       tmp_path: Path) -> None:
    """kill -9 of the driver at random moments after each new stored case (and of a busy
    worker once), three times; then the same command to the end: the store equals the
    uninterrupted one in every variable and every checksum holds."""
    out = tmp_path / "chaos.zarr"
    cmd = [GEARDYN, "sweep", str(spec_path), "--out", str(out), "--scheduler",
           cluster.scheduler.address]
    rng = random.Random(2026)
    at_kill = []
    for k in range(3):
        before = _stored(out)
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                start_new_session=True)
        t0 = time.perf_counter()
        while time.perf_counter() - t0 < 120 and proc.poll() is None and \
                _stored(out) < before + 1:
            time.sleep(0.02)
        if k == 1:  # a busy worker too
            busy = [w for w, keys in cluster.processing().items() if keys]
            if busy:
                pid = cluster.run(os.getpid, workers=busy[:1])[busy[0]]
                os.kill(pid, signal.SIGKILL)
        time.sleep(rng.uniform(0.0, 0.4))  # anywhere in the next case or its write
        with contextlib.suppress(ProcessLookupError):  # (it may have finished)
            os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate(timeout=60)
        at_kill.append(_stored(out))  # readable after every kill
    # killed mid-sweep (cases may finish in pairs on two workers: later kills may land after
    # the last case, while the driver writes the verdicts or closes the cluster)
    assert at_kill == sorted(at_kill) and 1 <= at_kill[0] < 4, at_kill
    cluster.wait_for_workers(2, timeout=120)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=240)
    assert r.returncode == 0, r.stdout + r.stderr
    if at_kill[-1] < 4:  # the last driver was killed mid-sweep, holding the lock: stale
        assert "warning: taking over the lock" in r.stdout, r.stdout + r.stderr
    same_store(reference, out)
    assert verify(out) == {}


def test_failed_cases_exit_non_zero_and_are_not_rerun(spec_path: Path, tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    from distributed import Client
    from typer.testing import CliRunner

    import geardyn.run
    from geardyn.cli import app

    calls: list[int] = []

    def broken(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        calls.append(1)
        raise RuntimeError("model broke")

    monkeypatch.setattr(geardyn.run, "run_simulation", broken)
    out = tmp_path / "failed.zarr"
    # an in-process cluster (the patched model runs in its worker thread) on tcp: --scheduler
    # takes network addresses only
    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=":0",
                protocol="tcp") as client:
        cmd = ["sweep", str(spec_path), "--out", str(out), "--scheduler",
               client.scheduler.address]
        r = CliRunner().invoke(app, cmd)
        assert r.exit_code == 1 and "4 of 4 case(s) failed" in r.output, r.output
        assert len(calls) == 4
        r = CliRunner().invoke(app, cmd)  # resume: the failed cases are not run again
        assert r.exit_code == 1 and len(calls) == 4, r.output
        assert "0 case(s) run now" in r.output
        r = CliRunner().invoke(app, [*cmd, "--retry-failed"])
        assert r.exit_code == 1 and len(calls) == 8, r.output
    assert list(statuses(out)) == ["failed"] * 4


def test_check_runs_the_run_time_checks(spec_path: Path, tmp_path: Path) -> None:
    """A time step that only the prepared model refuses is refused by --check (exit 2, the
    field and the case named, nothing created); a run too short for the diagnosis statistics
    is reported."""
    from typer.testing import CliRunner

    from geardyn.cli import app

    bad = tmp_path / "dt.toml"
    bad.write_text(SPEC + """
[[axes]]
name = "dt"
path = "planetary_dynamics.simulation.dt_s"
values = [1e-4, 2e-2]
""")
    out = tmp_path / "x.zarr"
    r = CliRunner().invoke(app, ["sweep", str(bad), "--out", str(out), "--check"])
    assert r.exit_code == 2, r.output
    assert "planetary_dynamics.simulation.dt_s" in r.output and "dt = 0.02" in r.output
    r = CliRunner().invoke(app, ["sweep", str(bad), "--out", str(out)])
    assert r.exit_code == 2 and not out.exists(), r.output
    r = CliRunner().invoke(app, ["sweep", str(bad), "--out", str(out), "--verify"])
    assert r.exit_code == 2 and "--out" in r.output and "does not exist" in r.output, r.output
    short = tmp_path / "short.toml"
    short.write_text(SPEC.replace("enabled = false", "enabled = true\nskip_s = 0.0"))
    r = CliRunner().invoke(app, ["sweep", str(short), "--out", str(out), "--check"])
    assert r.exit_code == 0, r.output
    text = r.output.replace("\n", " ")
    # the rule, and each case by its parameters with its components' revolutions (issue 18
    # part 7): 2 s hold 2 s × 40.5329 rpm / 60 = 1.35 sun-shaft revolutions
    assert "at least 4 whole own revolutions" in text, text
    assert "case 0 (motor_speed_rpm = 1187.5, rated = 1187.5, supply = 62.5, " in text
    assert "case 2 (motor_speed_rpm = 950.0" in text and "sun 1.4, " in text
    assert "(no component judgeable: the case will be 'not judged')" in text


def test_check_refuses_an_unstable_fe_time_step(tmp_path: Path) -> None:
    """FE transmission: a time step above the explicit stability limit 2/ω_max of the
    prepared model is refused by --check, naming the field and the case."""
    from typer.testing import CliRunner

    from geardyn.cli import app

    spec = tmp_path / "fe.toml"
    spec.write_text(f"""
[sweep]
base = "{ROOT / 'examples' / 'seed002_diagnose_spall.toml'}"
[run]
revolutions = 3.0
[[axes]]
name = "dt"
path = "transmission.simulation.time_step_s"
values = [1e-7, 1e-3]
[outputs.indicators]
enabled = false
""")
    r = CliRunner().invoke(app, ["sweep", str(spec), "--out", str(tmp_path / "fe.zarr"),
                                 "--check"])
    assert r.exit_code == 2, r.output
    text = r.output.replace("\n", " ")
    assert "[dt (2); product, 1 replicate(s)]" in text
    assert "case 1 (dt = 0.001): transmission.simulation.time_step_s" in text
    assert "stability limit" in text and "case 0" not in text
