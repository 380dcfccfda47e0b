"""Baseline runs of ``diagnose`` on worker processes (geardyn.diagnosis.parallel): the verdict
does not depend on the number of workers, a worker's error reaches the caller as the same
message, bad worker counts are messages."""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import pytest
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.diagnosis.parallel import check_workers, result, submit, worker_pool
from geardyn.errors import ConfigError, InputError
from tests.conftest import EXAMPLES
from tests.diagnosis.test_cli_diagnose import SENSORS

runner = CliRunner()


def _verdict(out: Path) -> dict:
    d = json.loads((out / "verdict.json").read_text())
    d.pop("created_utc")
    return d


def _square(x: float) -> float:
    return x * x


def test_pool_results_in_submission_order_and_no_pool_for_one_task():
    with worker_pool(2, 3) as pool:
        assert pool is not None
        tasks = [submit(pool, _square, (x,)) for x in (1.0, 2.0, 3.0)]
        assert [result(t) for t in tasks] == [1.0, 4.0, 9.0]
    with worker_pool(4, 1) as pool:
        assert pool is None
        assert result(submit(pool, _square, (5.0,))) == 25.0


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2"])
def test_bad_worker_counts_name_the_option(bad):
    with pytest.raises(InputError, match=r"--workers: must be a whole number ≥ 1"):
        check_workers(bad, "--workers")


def test_errors_cross_the_process_boundary_unchanged():
    e = pickle.loads(pickle.dumps(ConfigError(["a: rule one", "b: rule two"], source="m.toml")))
    assert e.problems == ["a: rule one", "b: rule two"] and e.source == "m.toml"
    assert str(e) == str(ConfigError(["a: rule one", "b: rule two"], source="m.toml"))


@pytest.fixture(scope="module")
def config(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("par") / "reclaimer.toml"
    path.write_text((EXAMPLES / "planetary_reclaimer.toml").read_text() + SENSORS)
    return path


ARGS = ["--t-end", "3", "--skip", "0.5", "--seeds", "0,1,2", "--blocks", "2"]


def test_verdict_is_the_same_on_one_or_two_workers(tmp_path: Path, config: Path):
    outs = []
    for n in ("1", "2"):
        out = tmp_path / f"w{n}"
        res = runner.invoke(app, ["diagnose", str(config), "--out", str(out), *ARGS,
                                  "--workers", n])
        assert res.exit_code == 0, res.output
        outs.append(_verdict(out))
    assert outs[0] == outs[1]
    assert [m["label"] for m in outs[1]["baseline"]["members"]] == [
        m["label"] for m in outs[0]["baseline"]["members"]]


def test_a_worker_error_is_the_callers_message(tmp_path: Path, config: Path, monkeypatch):
    import geardyn.diagnosis.pipeline as pipe

    check = pipe._check_status

    def failing(ds, what):  # baseline runs only: they run on the (forked) workers
        if what.startswith("healthy baseline"):
            raise InputError(f"{what}: simulated failure")
        check(ds, what)

    monkeypatch.setattr(pipe, "_check_status", failing)
    res = runner.invoke(app, ["diagnose", str(config), "--out", str(tmp_path / "o"), *ARGS,
                              "--workers", "2"])
    assert res.exit_code == 2, res.output
    assert "healthy baseline run 0 (seed 0), measurement 0: simulated failure" in " ".join(
        res.output.split())
    assert not (tmp_path / "o" / "verdict.json").exists()
