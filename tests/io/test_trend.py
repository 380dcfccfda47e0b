"""``geardyn trend`` (issue 19 part 4): the walkthrough of docs/measured.md (a folder of
measured-like records with a DC offset, a clipped stretch, a tacho with jitter and a missing
pulse, a dropout, and a growing pinion fault) run as written; the levels against Šidák's
formula; the store's idempotence and interrupted writes."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from geardyn.errors import InputError
from tests.conftest import EXAMPLES

runner = CliRunner()
DOC = EXAMPLES.parent / "docs" / "measured.md"


def _walkthrough():
    text = DOC.read_text()
    w = text[text.index("### Walkthrough"):]
    return (re.search(r"```toml\n(.*?)```", w, re.S).group(1),
            re.search(r"```python\n(.*?)```", w, re.S).group(1),
            re.search(r"```bash\n(.*?)```", w, re.S).group(1).split())


def test_walkthrough(tmp_path):
    from geardyn.cli import app

    toml, script, cmd = _walkthrough()
    (tmp_path / "pump.toml").write_text(toml)
    subprocess.run([sys.executable, "-c", script], cwd=tmp_path, check=True)
    assert cmd[:2] == ["geardyn", "trend"]
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        res = runner.invoke(app, cmd[1:])
        again = runner.invoke(app, cmd[1:])
    finally:
        os.chdir(cwd)
    text = " ".join(res.output.split())
    assert res.exit_code == 0, res.output
    assert "9 record(s) added, 0 already there, 1 not read" in text
    assert "pump_2026-03-06_08-00-00.csv: channel 'acc'" in text and "t = 4 s" in text
    assert "0 record(s) added, 9 already there" in " ".join(again.output.split())
    out = tmp_path / "trend"
    cross = pd.read_csv(out / "crossings.csv", parse_dates=["timestamp"])
    # nothing crosses before the fault (days 1–5 healthy reference, day 2 DC offset, day 4
    # missing pulse, day 5 clipped); the first faulty record alarms on the pinion's shaft and
    # warns on the pinion itself, whose alarm follows the next day (its SER spread raised to
    # its family's: baseline.family_floor)
    assert cross["timestamp"].min() == pd.Timestamp("2026-03-07 08:00:00")
    alarm = cross[cross["level"] == "alarm"].set_index("component")
    warning = cross[cross["level"] == "warning"].set_index("component")
    assert alarm.loc["input", "timestamp"] == pd.Timestamp("2026-03-07 08:00:00")
    assert warning.loc["input/z23", "timestamp"] == pd.Timestamp("2026-03-07 08:00:00")
    assert alarm.loc["input/z23", "timestamp"] == pd.Timestamp("2026-03-08 08:00:00")
    # z on the level's (log) scale: an alarm crossing is at least k_alarm σ of its level,
    # k_alarm = Φ⁻¹(1 − α) at the Šidák α of the m usable indicators (p_alarm 1 %)
    from scipy.stats import norm

    m = len(pd.read_csv(out / "levels.csv"))
    k_a = norm.isf(1 - (1 - 0.01) ** (1 / m))
    assert (alarm["z"] >= k_a * (1 - 1e-9)).all(), (alarm["z"], k_a)
    trend = pd.read_csv(out / "trend.csv")
    assert trend["key"].nunique() == 9
    assert (out / "report.html").read_text().count("data:image/png;base64,") == \
        trend["component"].nunique()


def test_levels_follow_sidak():
    """k of each level is Φ⁻¹(1 − α), α = 1 − (1 − P)^(1/m) over the m usable indicators;
    the level is exp(μ + k·σ) of the log values with σ the corrected spread (one value per
    reference record; positive indicators on the log scale)."""
    from scipy.stats import norm, t

    from geardyn.trend.levels import trend_levels

    rng = np.random.default_rng(2)
    refs = [pd.DataFrame({"component": ["a", "a", "b"], "kind": ["shaft"] * 3,
                          "indicator": ["FM4", "RMS", "FM4"], "channel": ["c"] * 3,
                          "value": 3 + 0.3 * rng.standard_normal(3), "block": 0})
            for _ in range(8)]
    lv = trend_levels(refs, p_warning=0.1, p_alarm=0.01)
    assert lv.tests == 3
    for p, k in ((0.1, lv.k_warning), (0.01, lv.k_alarm)):
        alpha = 1 - (1 - p) ** (1 / 3)
        assert k == pytest.approx(norm.isf(alpha), rel=1e-12)
    row = lv.table[(lv.table["component"] == "a") & (lv.table["indicator"] == "FM4")].iloc[0]
    vals = np.array([r["value"].iloc[0] for r in refs])
    n, k = vals.size, lv.k_alarm
    c = t.ppf(norm.cdf(k), n - 1) * math.sqrt(1 + 1 / n) / k  # small-sample factor
    logs = np.log(vals)  # a positive higher-is-worse indicator: log scale (docs/diagnosis.md)
    sigma = max(c * logs.std(ddof=1), math.log1p(0.05))
    assert row["alarm"] == pytest.approx(math.exp(logs.mean() + k * sigma), rel=1e-12)
    with pytest.raises(InputError, match="at least 2"):
        trend_levels(refs[:1])


def test_store_is_idempotent_and_ignores_interrupted_writes(tmp_path):
    from geardyn.trend.store import TrendStore, record_key

    (tmp_path / "not_a_store").mkdir()
    with pytest.raises(InputError, match="not a geardyn trend store"):
        TrendStore(tmp_path / "not_a_store")
    st = TrendStore(tmp_path / "h.zarr")
    f = tmp_path / "r.csv"
    f.write_text("1,2\n")
    table = pd.DataFrame({"component": ["a"] * 2, "kind": ["shaft"] * 2,
                          "indicator": ["FM4"] * 2, "channel": ["c"] * 2, "value": [1.0, 3.0],
                          "block": [0, 1]})
    info = {"file": str(f), "timestamp": "2026-01-01T00:00:00", "speed_rpm": 600.0}
    assert st.add(record_key(f), table, info) and not st.add(record_key(f), table, info)
    (tmp_path / "h.zarr" / "records" / ".tmp-dead").mkdir()  # a write killed before rename
    st = TrendStore(tmp_path / "h.zarr")
    assert st.keys() == {record_key(f)}
    h = st.table()
    assert len(h) == 1 and h["value"].iloc[0] == 2.0  # median over blocks


def test_cluster_workers_write_the_same_store(tmp_path):
    """On a 2-worker LocalCluster each worker writes the records it reads (in batches): the
    store holds the same rows as one written in this process, a record failing is reported
    and not stored, and re-running adds nothing."""
    from benchmarks.bench_trend import CONFIG, FS, _records

    import geardyn
    from geardyn.diagnosis.pipeline import options
    from geardyn.trend import TrendStore, update_store

    (tmp_path / "pump.toml").write_text(CONFIG.replace("50000.0", str(FS)))
    cfg = geardyn.load_config(tmp_path / "pump.toml")
    opts = options(cfg)
    paths = _records(tmp_path, 6)
    bad = tmp_path / "bad.npy"
    np.save(bad, np.zeros((10, 2), np.float32))
    one = update_store(TrendStore(tmp_path / "one.zarr"), paths, cfg, opts, workers=1)
    store = TrendStore(tmp_path / "two.zarr")
    two = update_store(store, [*paths, bad], cfg, opts, workers=2)
    assert sorted(two["added"]) == sorted(one["added"]) == sorted(map(str, paths))
    assert len(two["failed"]) == 1 and str(bad) in two["failed"][0]
    cols = ["key", "component", "indicator", "value"]
    a = TrendStore(tmp_path / "one.zarr").table()[cols].sort_values(cols[:3])
    b = store.table()[cols].sort_values(cols[:3])
    assert np.array_equal(a.to_numpy(), b.to_numpy())
    assert update_store(store, paths, cfg, opts, workers=2)["added"] == []
    assert not list((tmp_path / "two.zarr" / "records").glob(".tmp-*"))
