"""Measured records to a verdict (issue 19 part 3): a simulated fault run exported as a
measured file (volts of a 100 mV/g accelerometer, an analog 60-pulse tacho on the sun) and read
back through the [measurement] mapping gives the verdict of the simulated original against the
same simulated baselines; ``geardyn diagnose --record`` with measured baselines, with simulated
ones, and its errors (never the "add [[sensors]]" advice for a measured file)."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

import geardyn
from geardyn.cli import app
from tests.conftest import EXAMPLES
from tests.io.conftest import SENS_V_PER_MS2, analog_tacho

runner = CliRunner()
MAPPING = """
[measurement]
min_revolutions = 1.0
[[measurement.channels]]
name = "{name}"
source = "acc [V]"
location = "ring"
sensitivity = "100 mV/g"
[[measurement.channels]]
name = "sun_tacho"
source = "tacho [V]"
kind = "tacho"
shaft = "sun"
pulses_per_rev = 60
"""


def _config(tmp_path, base="seed004_diagnose_sun_crack.toml", name="ring_acc", extra=""):
    p = tmp_path / "measured.toml"
    p.write_text((EXAMPLES / base).read_text() + extra + MAPPING.format(name=name))
    return p


def export(ds, path, channel="ring_acc", sep=",", decimal="."):
    """A simulated run as a measured CSV: time, accelerometer volts, analog sun tacho."""
    from geardyn.results import channel as get

    ch = get(ds, channel)
    th = np.interp(ch.time, ds.time.values, ds.angle.sel(shaft="sun").values)
    pd.DataFrame({"time [s]": ch.time, "acc [V]": ch.values * SENS_V_PER_MS2,
                  "tacho [V]": analog_tacho(ch.time, th, 60)}).to_csv(
        path, sep=sep, decimal=decimal, index=False)
    return path


def test_measured_record_gives_the_simulated_verdict(tmp_path):
    """Seed 004 reclaimer, 20 % sun crack (examples/seed004_diagnose_sun_crack.toml, its
    [diagnosis] settings, baselines of seeds 0–2): the record of seed 100 judged as simulated
    (shaft angles from the model) and as a measured semicolon/decimal-comma CSV (reference
    angle from the 60-pulse analog tacho) get the same state on every component and the same
    location."""
    from geardyn.diagnosis.faults import healthy_variant
    from geardyn.diagnosis.features import features_from_result
    from geardyn.diagnosis.isolation import isolation_blocks
    from geardyn.diagnosis.pipeline import judge_features, options
    from geardyn.io import read_record
    from geardyn.run import run_simulation

    cfg = geardyn.load_config(_config(tmp_path))
    o = options(cfg)

    def features(ds):
        return (features_from_result(ds, cfg, o.channel, reference=o.reference,
                                     skip_s=o.skip_s, n_blocks=o.blocks),
                isolation_blocks(ds, cfg, o.channel, reference=o.reference, skip_s=o.skip_s))

    base = [features(run_simulation(healthy_variant(cfg), seed=s)) for s in (0, 1, 2)]

    def verdict(f):
        return judge_features(cfg, o, [b[0] for b in base], f[0],
                              baseline_blocks=[b[1] for b in base], record_blocks=f[1])

    rec = run_simulation(cfg, seed=100)
    simulated = verdict(features(rec))
    path = export(rec, tmp_path / "record.csv", sep=";", decimal=",")
    measured = verdict(features(read_record(path, cfg=cfg)))
    assert simulated.summary()["location"] == ["planetary.sun"]  # the example's own verdict
    assert measured.summary()["location"] == simulated.summary()["location"]
    assert {n: c.state for n, c in measured.components.items()} == \
        {n: c.state for n, c in simulated.components.items()}


@pytest.fixture(scope="module")
def short_runs(tmp_path_factory):
    """3 s runs of the reclaimer with a ring accelerometer (as tests/diagnosis/
    test_cli_diagnose.py): two healthy, one cracked, exported as measured CSVs."""
    from geardyn.diagnosis.faults import healthy_variant
    from geardyn.run import run_simulation
    from tests.diagnosis.test_cli_diagnose import SENSORS

    d = tmp_path_factory.mktemp("measured")
    cfg_path = _config(d, "planetary_reclaimer.toml", "acc_ring", SENSORS)
    cfg = geardyn.load_config(cfg_path)
    files = [export(run_simulation(c, seed=s, t_end_s=3.0),
                    d / f"{n}_2026-03-0{i + 1}_12-00-00.csv", channel="acc_ring")
             for i, (n, c, s) in enumerate((("h0", healthy_variant(cfg), 0),
                                             ("h1", healthy_variant(cfg), 1), ("rec", cfg, 100)))]
    return cfg_path, files


def test_cli_record_against_measured_baselines(tmp_path, short_runs):
    cfg_path, (h0, h1, rec) = short_runs
    out = tmp_path / "diag"
    res = runner.invoke(app, ["diagnose", str(cfg_path), "--out", str(out), "--record", str(rec),
                              "--baseline", str(h0), "--baseline", str(h1), "--skip", "0.5",
                              "--blocks", "2"])
    assert res.exit_code == 0, res.output
    assert "[[sensors]]" not in res.output
    d = json.loads((out / "verdict.json").read_text())
    assert d["record"]["file"] == str(rec)
    assert d["record"]["timestamp"] == "2026-03-03T12:00:00"  # from the file name
    assert d["record"]["speed_source"] == "tacho 'sun_tacho'"
    assert d["baseline"]["files"] == [str(h0), str(h1)]
    assert "planetary.sun" in d["components"] and (out / "report.html").is_file()


def test_cli_record_against_simulated_baselines(tmp_path, short_runs):
    """--record alone: the healthy machine is simulated (2 seeds) for as long as the record."""
    cfg_path, (_, _, rec) = short_runs
    out = tmp_path / "diag"
    res = runner.invoke(app, ["diagnose", str(cfg_path), "--out", str(out), "--record", str(rec),
                              "--seeds", "0,1", "--skip", "0.5", "--blocks", "2"])
    assert res.exit_code == 0, res.output
    d = json.loads((out / "verdict.json").read_text())
    assert d["baseline"]["seeds"] == [0, 1] and d["baseline"]["t_end_s"] == pytest.approx(3.0)
    assert d["channels"] == ["acc_ring"]


@pytest.fixture
def no_simulation(monkeypatch):
    def boom(*a, **k):
        raise AssertionError("a simulation ran before the input error")

    monkeypatch.setattr("geardyn.run.run_simulation", boom)


def test_cli_measured_errors_come_first(tmp_path, short_runs, no_simulation):
    cfg_path, (_, _, rec) = short_runs
    res = runner.invoke(app, ["diagnose", str(EXAMPLES / "seed004_diagnose_sun_crack.toml"),
                              "--out", str(tmp_path / "o"), "--record", str(rec)])
    text = " ".join(res.output.split())
    assert res.exit_code == 2 and "is a measured file; map its channels" in text
    assert "[[sensors]]" not in text
    bad = tmp_path / "other.toml"
    bad.write_text(cfg_path.read_text().replace('name = "acc_ring"\nsource',
                                                'name = "acc_x"\nsource'))
    res = runner.invoke(app, ["diagnose", str(bad), "--out", str(tmp_path / "o"), "--record",
                              str(rec)])
    text = " ".join(res.output.split())
    assert res.exit_code == 2 and "channel 'acc_x' has no simulated counterpart" in text
    res = runner.invoke(app, ["diagnose", str(cfg_path), "--out", str(tmp_path / "o"),
                              "--record", str(rec), "--channel", "nope"])
    text = " ".join(res.output.split())
    assert res.exit_code == 2 and "map it in [[measurement.channels]]" in text


def test_measured_and_simulated_baselines_together(tmp_path, short_runs):
    """Both kinds of baseline: the simulated channel is scaled to the measured healthy level
    (ratio of median RMS, > 0 and finite), the files and the seeds are both recorded."""
    from geardyn.diagnosis.measured import diagnose_record

    cfg_path, (h0, h1, rec) = short_runs
    cfg = geardyn.load_config(cfg_path)
    v = diagnose_record(cfg, rec, tmp_path / "o", baseline_paths=[h0, h1], simulate=True,
                        baseline_seeds=[0], skip_s=0.5, n_blocks=2)
    d = json.loads((tmp_path / "o" / "verdict.json").read_text())
    assert d["baseline"]["files"] == [str(h0), str(h1)] and d["baseline"]["seeds"] == [0]
    # the exported files hold the simulated channel itself: the level ratio is 1 up to the
    # seeds' differences (noise, errors): well within a factor 2
    assert 0.5 < d["baseline"]["simulated_scale"] < 2.0
    assert v.summary()["verdict"] in ("alarm", "healthy", "uncertain")


def test_docs_mapping_example_is_a_valid_config():
    """The [measurement] example of docs/measured.md loads with the seed 004 machine."""
    import re
    import tomllib

    from geardyn.config.loader import parse_config

    text = (EXAMPLES.parent / "docs" / "measured.md").read_text()
    block = re.search(r"```toml\n(.*?)```", text, re.S).group(1)
    data = tomllib.loads((EXAMPLES / "seed004_diagnose_sun_crack.toml").read_text() + block)
    cfg = parse_config(data)
    assert [c.name for c in cfg.measurement.channels] == ["ring_acc", "sun_tacho"]


def test_trend_levels_from_simulated_runs(short_runs):
    """The trend's --simulate-baseline reference: features of the measured channel's
    [[sensors]] counterpart in simulated healthy runs (1 run × 2 measurements of the
    ensemble), turned into levels; a channel without counterpart is refused."""
    from geardyn.diagnosis.measured import simulated_reference
    from geardyn.diagnosis.pipeline import options
    from geardyn.errors import InputError
    from geardyn.trend.levels import trend_levels

    cfg = geardyn.load_config(short_runs[0])
    opts = options(cfg, t_end_s=3.0, baseline_seeds=[0], skip_s=0.5, blocks=2)
    feats = simulated_reference(cfg, opts, "acc_ring")
    assert len(feats) == 2
    tables = [f.table.groupby(["component", "kind", "indicator", "channel"])["value"].median()
              .reset_index().assign(block=0) for f in feats]
    lv = trend_levels(tables, source="simulated")
    assert len(lv.table) and (lv.table["alarm"] > lv.table["warning"]).all()
    with pytest.raises(InputError, match="'ghost' has no simulated counterpart"):
        simulated_reference(cfg, opts, "ghost")


def test_one_override_list_serves_every_entry_point(tmp_path):
    """diagnose, diagnose_files and diagnose_record take the same [diagnosis] overrides
    (pipeline.Overrides): renamed fields mapped, a keyword that does not apply refused."""
    from geardyn.diagnosis.measured import diagnose_record
    from geardyn.diagnosis.pipeline import diagnose_files, options_from

    cfg = geardyn.load_config(EXAMPLES / "seed004_planetary.toml")
    o = options_from(cfg, {"k": 4.5, "n_blocks": 3, "skip_s": None}, "diagnose")
    assert (o.threshold_k, o.blocks) == (4.5, 3)
    with pytest.raises(TypeError, match="diagnose_files.*t_end_s"):
        diagnose_files(["h.nc"], "r.nc", cfg, tmp_path, t_end_s=3.0)
    with pytest.raises(TypeError, match="diagnose_record.*record_seed"):
        diagnose_record(cfg, "r.nc", tmp_path, record_seed=5)
    with pytest.raises(TypeError, match="blocks"):
        options_from(cfg, {"blocks": 3}, "diagnose")
