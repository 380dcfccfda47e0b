"""The detectability study (geardyn.studies): its design, its statistics and its runner.

* design: ≥ 300 records over both simulators, every machine split in two halves before any
  run, the same design for the same seed;
* Clopper–Pearson against its closed forms: k = 0 → upper bound 1 − (α/2)^(1/n); k = n → lower
  bound (α/2)^(1/n) (Clopper & Pearson 1934);
* the runner on a small configuration (2 baseline runs × 1 measurement, 12 s): a healthy record
  of the fleet and a 30 % sun crack, rows with the verdict and a paired SNR.
"""

from __future__ import annotations

import math
from collections import Counter

import pandas as pd
import pytest

from geardyn.studies.detectability import (
    CONFIGURATIONS,
    clopper_pearson,
    design,
    page,
    statistics,
)
from geardyn.studies.runner import Configuration, RecordSpec, read_rows, run_configuration


def test_design_covers_both_simulators_and_is_split_before_running():
    confs = design()
    assert design() == confs  # deterministic
    records = sum(len(c.records) for c in confs)
    assert records >= 300
    by_machine = Counter(c.machine for c in confs)
    assert dict(by_machine) == CONFIGURATIONS
    for m, n in CONFIGURATIONS.items():
        halves = Counter(c.half for c in confs if c.machine == m)
        assert halves["tune"] == n // 2 and halves["report"] == n - n // 2
    kinds = {r.fault_type for c in confs for r in c.records}
    assert {"sun crack", "ring crack", "planet crack", "bearing outer-race spall",
            "tooth spall", "tooth crack", "healthy"} <= kinds
    for c in confs:  # three sizes per fault kind, healthy records at every operating point
        sizes = Counter(r.fault_type for r in c.records)
        assert sizes["healthy"] == 4 and all(v == 3 for k, v in sizes.items() if k != "healthy")
    assert len({c.fleet_seed for c in confs}) == len(confs)  # other machines per configuration
    assert len({c.params["planets"] for c in confs}) == 3  # 3 and 4 planets, FE (0)
    assert design(seed=1) != confs


def test_clopper_pearson_closed_forms():
    for n in (5, 20, 100):
        lo, hi = clopper_pearson(0, n)
        assert lo == 0.0 and hi == pytest.approx(1 - 0.025 ** (1 / n), rel=1e-9)
        lo, hi = clopper_pearson(n, n)
        assert hi == 1.0 and lo == pytest.approx(0.025 ** (1 / n), rel=1e-9)
    lo, hi = clopper_pearson(5, 10)
    assert lo < 0.5 < hi and lo == pytest.approx(1 - hi, rel=1e-9)  # symmetric at k = n/2


def _rows():
    base = {"config": "c", "machine": "m", "status": "ok", "level": "", "planet_named": None}
    rows = []
    for i in range(40):
        rows.append({**base, "config": f"c{i % 4}", "half": "report" if i % 2 else "tune",
                     "fault_type": "healthy", "severity": 0.0, "detected": i == 3,
                     "verdict": "alarm" if i == 3 else "healthy", "localised": None,
                     "snr": 0.0})
    for i in range(30):
        det = i % 3 != 0
        rows.append({**base, "config": f"c{i % 4}", "half": "report" if i % 2 else "tune",
                     "fault_type": "sun crack", "severity": 0.1 * (1 + i % 3), "detected": det,
                     "verdict": "alarm" if det else "healthy", "localised": det and i % 5 != 0,
                     "snr": 10.0 ** (i % 4)})
    return pd.DataFrame(rows)


def test_statistics_count_what_the_page_says():
    rows = _rows()
    st = statistics(rows, "report")
    rep = rows[rows["half"] == "report"]
    h = rep[rep["fault_type"] == "healthy"]
    assert st["false_alarm"]["k"] == int(h["detected"].sum()) == 1
    assert st["false_alarm"]["n"] == len(h) == 20
    f = rep[rep["fault_type"] != "healthy"]
    assert st["detection"]["k"] == int(f["detected"].sum())
    d = f[f["detected"]]
    assert st["isolation"]["n"] == len(d) and st["isolation"]["k"] == int(d["localised"].sum())
    assert st["detected_reported_healthy"] == 0
    assert sum(r["n"] for r in st["pod"].values()) == len(f)
    assert sum(r["n"] for r in st["pod_snr"].values()) == len(f)
    text = page(rows, 0.01, "cmd", 3600.0)
    assert "1/20 = 5.0 %" in text and "## Tune half" in text


@pytest.mark.slow
def test_runner_on_a_small_configuration(examples_dir, tmp_path):
    base = tmp_path / "small.toml"
    src = (examples_dir / "seed004_diagnose_sun_crack.toml").read_text()
    src = src.replace("t_end_s = 50.0", "t_end_s = 12.0")
    base.write_text(src + "\n[diagnosis.ensemble]\nmembers = 2\nmeasurements_per_run = 1\n")
    path = "planetary_dynamics.stages[0].faults"
    conf = Configuration(
        "t-00", "planetary 3 planets", "report", str(base),
        {"sensors[0].noise_rms": 0.02}, 1.0, 1.0,
        (RecordSpec("healthy", "healthy", 0.0, {}, 100),
         RecordSpec("sun crack 30 %", "sun crack", 0.3,
                    {path: [{"kind": "crack", "gear": "sun", "crack_fraction": 0.3}]}, 100)),
        {"sensor": "ring 0°"})
    out = tmp_path / "out"
    rows = run_configuration(conf, out / "cases" / "t-00.pkl")
    assert [r["status"] for r in rows] == ["ok", "ok"], rows
    healthy, crack = rows
    assert healthy["fault_type"] == "healthy" and healthy["snr"] == 0.0
    assert crack["snr"] > 1.0 and math.isfinite(crack["snr"])
    assert crack["expected"] == "planetary.sun"
    for r in rows:
        assert r["verdict"] in ("alarm", "uncertain", "healthy")
        assert r["tests"] > 0 and 0 < r["alpha_per_test"] < 0.01
        assert not (r["detected"] and r["verdict"] == "healthy")
    # rows are stored as JSON, readable back; judged again from the cache, the same rows
    from geardyn.studies.runner import _write_rows, rejudge

    (out / "rows").mkdir(parents=True)
    _write_rows(out / "rows" / "t-00.json", rows)
    assert read_rows(out)[1]["record"] == "sun crack 30 %"
    assert rejudge(out) == 1
    again = read_rows(out)
    for a, b in zip(rows, again, strict=True):
        assert {k: a[k] for k in ("verdict", "location", "tests", "first_alarm")} == \
               {k: b[k] for k in ("verdict", "location", "tests", "first_alarm")}


def test_the_page_is_generated_from_the_stored_rows():
    """docs/detectability.md is page() of the study's rows kept in docs/data (the study's own
    output, not a reference: this test keeps the page and its data together)."""
    import gzip
    import json
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    with gzip.open(root / "docs" / "data" / "detectability_rows.json.gz", "rt") as fh:
        rows = pd.DataFrame(json.load(fh))
    text = (root / "docs" / "detectability.md").read_text()
    cpu_line = next(line for line in text.splitlines() if line.startswith("Regenerate:"))
    cpu = float(cpu_line.split("(")[1].split()[0]) * 3600.0
    want = page(rows, 0.01, "python -m geardyn.studies.detectability --out study --docs docs",
                cpu)
    assert want.splitlines() == text.splitlines()
    st = statistics(rows, "report")
    assert st["records"] >= 150 and st["detected_reported_healthy"] == 0


@pytest.mark.parametrize(("argv", "named"), [
    (["--workers", "0"], "--workers"), (["--only", "nope"], "--only")])
def test_study_command_refuses_bad_options(tmp_path, capsys, argv, named):
    from geardyn.studies.detectability import main

    with pytest.raises(SystemExit) as exc:
        main(["--out", str(tmp_path / "s"), *argv])
    assert exc.value.code == 2 and named in capsys.readouterr().err


#: A tiny study: one configuration per machine, 2 healthy records and the largest fault of
#: one kind, a baseline of 2 runs × 1 measurement, planetary runs of 12 s.
SMALL = {"diagnosis.baseline_seeds": [0, 1], "diagnosis.ensemble.measurements_per_run": 1}
TINY_EXTRA = {"planetary 3 planets": {**SMALL, "planetary_dynamics.simulation.t_end_s": 12.0},
              "planetary 4 planets": {**SMALL, "planetary_dynamics.simulation.t_end_s": 12.0},
              "FE transmission": SMALL}


def _tiny():
    from dataclasses import replace

    confs = design(counts={m: 1 for m in CONFIGURATIONS})
    keep = ("sun crack 30%", "planet crack 30%", "outer-race spall 20°")
    return [replace(c, records=tuple(r for r in c.records
                                     if (r.fault_type == "healthy" and r.seed in (100, 101))
                                     or r.label in keep)[:3]) for c in confs]


def test_study_specs_hold_the_design():
    """One spec per machine: records and configurations as two zipped groups combined as a
    product, every case config the configuration's healthy config with the record's faults
    (checked by specs() itself), records first; the planetary run length from the verdict."""
    from geardyn.studies.detectability import study_specs
    from geardyn.studies.sweeps import toml_dumps
    from geardyn.sweep.spec import from_dict
    from geardyn.sweep.verdicts import diagnosis_run_length_s

    confs = design(counts={m: 2 for m in CONFIGURATIONS})
    sts = study_specs(confs)
    assert sum(len(st.configurations) for st in sts) == len(confs)
    for st in sts:
        sw = from_dict(st.spec)
        assert sw.spec.outputs.diagnosis.record_machine == "fleet"
        groups = list(dict.fromkeys(a.group for a in sw.axes))
        assert groups == ["records", "configuration"]
        n_rec = len(st.configurations[0].records)
        assert len(sw.cases) == n_rec * len(st.configurations)
        labels = [c.labels(sw.axes) for c in sw.cases]
        assert labels[0]["configuration"] == st.configurations[0].id
        assert labels[1]["record"] == labels[0]["record"] or len(st.configurations) == 1
        assert {x["half"] for x in labels} <= {"tune", "report"}
        assert sorted({(x["record"], c.seed) for x, c in zip(labels, sw.cases,
                                                             strict=True)}) == sorted(
            {(r.label, r.seed) for r in st.configurations[0].records})
        # the generated TOML is the same spec
        import tomllib

        assert from_dict(tomllib.loads(toml_dumps(st.spec))).spec_hash == sw.spec_hash
        if st.configurations[0].machine.startswith("planetary"):
            from geardyn.studies.sweeps import configuration_config

            for k, c in enumerate(st.configurations):
                cfg = configuration_config(c, run_length=False)
                t = sw.case_config(next(x for x in sw.cases if x.value_index[
                    [a.name for a in sw.axes].index("configuration")] == k))
                need = diagnosis_run_length_s(cfg)
                got = t["planetary_dynamics"]["simulation"]["t_end_s"]
                assert need <= got < need + 0.1 + 1e-9


@pytest.mark.slow
def test_tiny_study_runs_through_geardyn_sweep(tmp_path):
    """The tiny study run by the study's sweep specs (LocalCluster of 2 workers): rows with
    the verdict, SNR and CPU times, one cached baseline per configuration, the written specs
    re-run by `geardyn sweep` with nothing left to run, statistics and page from the rows."""
    import time

    from geardyn.studies.detectability import run_sweeps, write_rows
    from geardyn.sweep import load_spec, run

    confs = _tiny()
    out = tmp_path / "study"
    t0 = time.perf_counter()
    rows = run_sweeps(confs, out, workers=2, extra=TINY_EXTRA, run_length=False)
    wall = time.perf_counter() - t0
    assert len(rows) == sum(len(c.records) for c in confs) == 9
    assert [r["status"] for r in rows] == ["ok"] * 9, [r["status"] for r in rows]
    for r in rows:
        assert r["verdict"] in ("alarm", "uncertain", "healthy")
        assert r["tests"] > 0 and 0 < r["alpha_per_test"] < 0.01
        assert not (r["detected"] and r["verdict"] == "healthy")
        assert r["record_cpu_s"] > 0 and r["baseline_cpu_s"] > 0
        if r["fault_type"] == "healthy":
            assert r["snr"] == 0.0
        else:
            assert r["snr"] > 0 and r["expected"]
    for c in confs:  # one baseline per configuration: its CPU time read from the cache
        assert len({r["baseline_cpu_s"] for r in rows if r["config"] == c.id}) == 1
    specs = sorted(out.glob("*.toml"))
    assert len(specs) == 3 and all(p.with_suffix(".zarr").is_dir() for p in specs)
    for p in specs:  # one baseline per configuration, shared by its records
        assert len(list((p.with_suffix(".zarr") / "diagnosis_cache").glob("baseline-*"))) == 1
        again = run(load_spec(p), p.with_suffix(".zarr"), n_workers=1)
        assert again.run == 0
    df = pd.DataFrame(rows)
    st = statistics(df, None)
    assert st["records"] == 9 and st["failed"] == 0 and st["detected_reported_healthy"] == 0
    text = page(df, 0.01, "cmd", float(df["record_cpu_s"].sum()))
    assert "## Tune half" in text
    write_rows(rows, tmp_path / "rows.json.gz")
    import gzip
    import json

    with gzip.open(tmp_path / "rows.json.gz", "rt") as fh:
        assert len(json.load(fh)) == 9
    cpu = df.drop_duplicates("config")["baseline_cpu_s"].sum() + df["record_cpu_s"].sum()
    print(f"tiny study: {wall:.0f} s wall, {cpu:.0f} s worker CPU")


def test_configurations_with_their_own_records_get_their_own_spec_files():
    """Configurations of one machine whose record sets differ (here: other run seeds) are
    other sweeps: each gets a file of its own, none overwrites another (was: one slug per
    machine and planet, the last spec written won)."""
    from dataclasses import replace

    from geardyn.studies.detectability import study_specs

    confs = [c for c in design(counts={m: 2 for m in CONFIGURATIONS})
             if c.machine == "FE transmission"]
    confs = [confs[0], replace(confs[1], records=tuple(replace(r, seed=r.seed + 50)
                                                      for r in confs[1].records))]
    sts = study_specs(confs)
    assert len(sts) == 2 and len({st.slug for st in sts}) == 2
    assert sum(len(st.configurations) for st in sts) == 2
