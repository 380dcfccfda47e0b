"""``[outputs.diagnosis]``: each case judged as ``geardyn diagnose`` judges its config.

* spec errors name the field (replicates, an unknown option, a record seed that is a
  baseline seed);
* on a small config (seed 004 for 12 s, a baseline of 2 runs × 1 measurement) the stored
  verdict of a 30 % sun crack is the one :func:`geardyn.diagnosis.pipeline.diagnose` writes for
  the same config (state, location, tests, α, first alarm), the healthy cases of two seeds
  share one cached baseline, the healthy case's SNR is 0 and the crack's is positive; a
  second run resumes (nothing runs);
* the cache lock: a second holder waits, a lock left by a process that is gone is taken over;
* the planetary run length of :func:`geardyn.sweep.verdicts.diagnosis_run_length_s` gives
  every planet of the 3-planet stage 2 planet-separated rows at the ensemble's slowest speed
  (the rule: (2 + 1)·M − 1 passes, M = 3 passes per row, plus a window of 13 + 1 ring teeth).
"""

from __future__ import annotations

import json
import math
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from geardyn.errors import ConfigError
from geardyn.sweep.spec import from_dict

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / "examples" / "seed004_diagnose_sun_crack.toml"
FAULTS = "planetary_dynamics.stages[0].faults"
CRACK = [{"kind": "crack", "gear": "sun", "crack_fraction": 0.3}]


def _spec(base: Path | str = BASE, **outputs: object) -> dict:
    return {
        "sweep": {"base": str(base)},
        "axes": [
            {
                "name": "record",
                "path": FAULTS,
                "values": [[], CRACK, []],
                "labels": ["healthy", "sun crack", "healthy 101"],
                "group": "r",
            },
            {
                "name": "record_seed",
                "path": "diagnosis.record_seed",
                "values": [100, 100, 101],
                "group": "r",
            },
        ],
        "outputs": {"indicators": {"enabled": False}, "diagnosis": dict(outputs)},
    }


def _problems(data: dict) -> str:
    with pytest.raises(ConfigError) as info:
        from_dict(data)
    return str(info.value)


def test_diagnosis_spec_errors_name_the_field() -> None:
    sw = from_dict(_spec())
    assert [c.seed for c in sw.cases] == [100, 100, 101]  # the configs' record seeds
    bad = _spec()
    bad["sweep"]["replicates"] = 2
    assert "sweep.replicates" in _problems(bad) and "diagnosis.record_seed" in _problems(bad)
    bad = _spec(record_machine="fleet", fleet_seeds=3)
    assert "outputs.diagnosis.fleet_seeds" in _problems(bad)
    bad = _spec(record_machine="twin")
    assert "outputs.diagnosis.record_machine" in _problems(bad)
    bad = _spec()
    bad["axes"][1]["values"] = [100, 100, 1]  # seed 1 is a baseline seed of the example
    text = _problems(bad)
    assert "diagnosis.record_seed: 1 is also a baseline seed" in text and "case 2" in text


@pytest.fixture(scope="module")
def small(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("diag")
    src = BASE.read_text().replace("t_end_s = 50.0", "t_end_s = 12.0")
    base = d / "small.toml"
    base.write_text(src + "\n[diagnosis.ensemble]\nmembers = 2\nmeasurements_per_run = 1\n")
    return base


@pytest.mark.slow
def test_cases_are_judged_as_geardyn_diagnose(small: Path, tmp_path: Path) -> None:
    from geardyn.config.loader import load_config, parse_config
    from geardyn.diagnosis.pipeline import diagnose
    from geardyn.sweep import load_spec, open_dataset, run
    from geardyn.sweep.spec import set_path

    spec_path = tmp_path / "spec.json.toml"
    from geardyn.studies.sweeps import toml_dumps

    spec_path.write_text(toml_dumps(_spec(small)))
    out = tmp_path / "diag.zarr"
    t0 = time.process_time()
    summary = run(spec_path, out, n_workers=2)
    assert summary.run == 3 and summary.failed_total == 0
    ds = open_dataset(out).load()
    assert list(ds["status"].values) == ["ok"] * 3, list(ds["message"].values)
    assert list(ds["seed"].values) == [100, 100, 101]
    d = {k.split(".", 1)[1]: ds[k].values for k in ds.data_vars if k.startswith("diagnosis.")}
    # one baseline for the three cases (one healthy config), simulated once and cached
    assert len(set(d["baseline"])) == 1
    assert len(set(d["baseline_cpu_s"])) == 1  # read from the cache, not simulated again
    assert len(list((out / "diagnosis_cache").glob("baseline-*.pkl"))) == 1
    assert d["snr"][0] == 0.0 and d["snr"][2] == 0.0 and d["snr"][1] > 1.0
    assert list(d["expected"]) == ["", "planetary.sun", ""]
    # the crack's verdict is the one geardyn diagnose writes for the same config
    data = load_config(small).model_dump(mode="json")
    set_path(data, FAULTS, CRACK)
    v = diagnose(parse_config(data), tmp_path / "verdict", workers=1)
    s = v.summary()
    det = v.detection or {}
    assert d["verdict"][1] == s["verdict"]
    assert d["location"][1] == ", ".join((v.localisation or {}).get("components") or [])
    assert d["tests"][1] == det["tests"]
    assert d["alpha_per_test"][1] == pytest.approx(det["alpha_per_test"], rel=1e-12)
    alarms = det.get("alarms") or []
    assert d["first_alarm"][1] == (
        f"{alarms[0]['component']} {alarms[0]['indicator']}" if alarms else ""
    )
    if alarms:
        assert d["first_margin"][1] == pytest.approx(alarms[0]["margin"], rel=1e-12)
    assert d["detected"][1] == float(bool(det.get("detected")))
    # resumed: nothing runs again, the store is the one spec's
    again = run(load_spec(spec_path), out, n_workers=1)
    assert again.run == 0 and again.skipped == 3
    print(f"3 cases + diagnose: {time.process_time() - t0:.1f} s driver CPU")


def test_wait_lock_waits_and_takes_over_a_dead_holder(tmp_path: Path) -> None:
    from geardyn.sweep.lock import wait_lock

    target = tmp_path / "entry.pkl"
    order: list[str] = []

    def second() -> None:
        order.append("second in")
        with wait_lock(target):
            order.append("second got it")

    with wait_lock(target):
        t = threading.Thread(target=second)
        t.start()
        time.sleep(0.5)
        order.append("first out")
    t.join(10)
    assert order == ["second in", "first out", "second got it"]
    assert not Path(str(target) + ".lock").exists()
    # a lock of a process that is gone (same host, no such pid) is taken over
    import socket

    Path(str(target) + ".lock").write_text(
        json.dumps({"pid": 2**22 + 17, "host": socket.gethostname(), "start_ticks": "1"})
    )
    t0 = time.perf_counter()
    with wait_lock(target) as info:
        assert json.loads(Path(str(target) + ".lock").read_text())["pid"] == info["pid"]
    assert time.perf_counter() - t0 < 5.0
    assert not Path(str(target) + ".lock").exists()


def test_planet_run_length_gives_every_planet_two_rows() -> None:
    from geardyn.config.loader import load_config
    from geardyn.diagnosis.ensemble import operating_point
    from geardyn.diagnosis.faults import healthy_variant
    from geardyn.diagnosis.planets import passes_per_row, planet_domains
    from geardyn.run import run_simulation
    from geardyn.sweep.verdicts import MIN_PLANET_ROWS, diagnosis_run_length_s

    cfg = healthy_variant(load_config(BASE))
    m = passes_per_row(83, 32, 13)
    assert m == 3
    carrier = 19 / (19 + 83)  # carrier revolutions per sun revolution (Willis, fixed ring)
    revs = ((MIN_PLANET_ROWS + 1) * m - 1 + 14 / 83) / carrier
    tol = cfg.diagnosis.ensemble.speed_tolerance
    want = cfg.diagnosis.skip_s + revs / (cfg.input_speeds_rpm["sun"] * (1 - tol) / 60)
    t = diagnosis_run_length_s(cfg)
    assert t == pytest.approx(want, rel=1e-9)
    slow = operating_point(cfg, 1 - tol, 1.0)
    ds = run_simulation(slow, seed=100, t_end_s=t)
    rows = planet_domains(ds, slow, "ring_acc", skip_s=cfg.diagnosis.skip_s)
    assert len(rows) == 3 and all(r.shape[0] >= MIN_PLANET_ROWS for r in rows.values())
    assert math.isfinite(t) and np.isfinite(list(rows.values())[0]).all()


def test_check_names_cases_too_short_to_name_a_planet(small: Path, tmp_path: Path) -> None:
    """`geardyn sweep --check`: a 12 s seed 004 record holds 6.2 sun revolutions after
    skip_s, a planet needs 43.9 (8.17 carrier revolutions); 90 s runs are long enough."""
    from typer.testing import CliRunner

    from geardyn.cli import app
    from geardyn.studies.sweeps import toml_dumps
    from geardyn.sweep.verdicts import planet_row_notes

    notes = planet_row_notes(from_dict(_spec(small)))
    assert len(notes) == 2 and "run too short to name a planet" in notes[0]
    assert "6.22 reference revolutions" in notes[1] and "43.9 give every planet" in notes[1]
    long = _spec(small)
    long["run"] = {"t_end_s": 90.0}
    assert planet_row_notes(from_dict(long)) == []
    p = tmp_path / "spec.toml"
    p.write_text(toml_dumps(_spec(small)))
    r = CliRunner().invoke(
        app, ["sweep", str(p), "--out", str(tmp_path / "x.zarr"), "--check"], terminal_width=400
    )
    assert r.exit_code == 0, r.output
    assert "too short to name a planet" in r.output


def test_a_baseline_that_fails_is_cached_as_a_failure(small: Path, tmp_path: Path) -> None:
    """Every case of a machine whose baseline cannot be simulated fails with the reason,
    the second without simulating it again."""
    from geardyn.config.loader import load_config
    from geardyn.errors import InputError
    from geardyn.sweep import diagnosis as dg

    rec = dg.record(load_config(small), 100, {}, {})
    calls = []

    def boom(r: object) -> dict:
        calls.append(r)
        raise ValueError("static equilibrium did not converge")

    store = tmp_path / "s.zarr"
    store.mkdir()
    orig = dg._simulate_baseline
    dg._simulate_baseline = boom
    try:
        for _ in range(2):
            with pytest.raises(InputError, match="static equilibrium did not converge"):
                dg.baseline(rec, str(store))
    finally:
        dg._simulate_baseline = orig
    assert len(calls) == 1


def test_fleet_records_of_two_configs_never_share_a_run_seed() -> None:
    """A fleet machine's run seed mixes the record seed with its healthy config: records of
    one seed at two operating points are two machines (their own seed 004 manufacturing
    errors and sensor noise), a fault record and the healthy record of its seed share one
    (the SNR's pairing); a nominal record runs with the case's seed."""
    from geardyn.config.loader import load_config, parse_config
    from geardyn.sweep.diagnosis import fleet_run_seed, record
    from geardyn.sweep.spec import set_path

    data = load_config(BASE).model_dump(mode="json")
    set_path(data, FAULTS, [])
    healthy = parse_config(data)
    faulty = parse_config({**data, "planetary_dynamics": {
        **data["planetary_dynamics"],
        "stages": [{**data["planetary_dynamics"]["stages"][0], "faults": CRACK}]}})
    other = json.loads(json.dumps(data))
    other["input_speeds_rpm"] = {k: 1.1 * v for k, v in data["input_speeds_rpm"].items()}
    other = parse_config(other)
    fleet = {"record_machine": "fleet"}
    a, f, b = (record(c, 100, {}, fleet) for c in (healthy, faulty, other))
    assert a.run_seed == f.run_seed == fleet_run_seed(100, a.healthy_key)
    assert b.run_seed != a.run_seed and record(healthy, 101, {}, fleet).run_seed != a.run_seed
    assert record(healthy, 100, {}, fleet).run_seed == a.run_seed  # reproducible
    assert record(healthy, 100, {}, {}).run_seed == 100
