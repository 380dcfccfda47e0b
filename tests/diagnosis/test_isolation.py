"""Isolation statistics against closed forms.

The synchronous deviation ratio is the F statistic of a one-way ANOVA of the revolutions: for
Gaussian noise alone its mean is ν₂/(ν₂ − 2) ≈ 1 (ν₂ = samples·(R − 1) denominator degrees of
freedom); a pattern repeated in every revolution with power P on noise of variance σ² raises it
to ≈ 1 + R·P/σ²; a pattern whose position drifts between revolutions does not.
"""

from __future__ import annotations

import numpy as np
import pytest

import geardyn
from geardyn.diagnosis.isolation import (
    line_family_shares,
    revolution_blocks,
    synchronous_deviation_ratio,
)
from geardyn.errors import InputError

SPR, R = 256, 12


def _noise(seed, sigma=1.0):
    return np.random.default_rng(seed).normal(0.0, sigma, (R, SPR))


def test_sdr_null_is_one():
    vals = [synchronous_deviation_ratio(_noise(s), np.zeros(SPR)) for s in range(200)]
    nu2 = SPR * (R - 1)
    assert np.mean(vals) == pytest.approx(nu2 / (nu2 - 2), abs=0.02)
    assert np.std(vals) < 0.15


def test_sdr_of_a_synchronous_pattern():
    """Closed form for a pattern of power P repeated in every revolution: 1 + R·P/σ²."""
    theta = 2 * np.pi * np.arange(SPR) / SPR
    pattern = 0.3 * np.exp(-0.5 * ((theta - 2.0) / 0.1) ** 2)
    p = float(np.mean(pattern**2))
    vals = [synchronous_deviation_ratio(_noise(s) + pattern, np.zeros(SPR)) for s in range(100)]
    assert np.mean(vals) == pytest.approx(1 + R * p / 1.0, rel=0.1)
    # the same pulse drifting by a quarter revolution each revolution is not synchronous
    drift = np.array([np.roll(pattern, r * SPR // 4 + r) for r in range(R)])
    vals = [synchronous_deviation_ratio(_noise(s) + drift, np.zeros(SPR)) for s in range(100)]
    assert np.mean(vals) < 1.2


def test_sdr_reference_is_subtracted_and_errors():
    base = np.sin(2 * np.pi * 5 * np.arange(SPR) / SPR)
    rec = _noise(1) * 1e-3 + base
    assert synchronous_deviation_ratio(rec, base) == pytest.approx(1.0, abs=0.3)
    assert synchronous_deviation_ratio(np.tile(base, (3, 1)), base) == 0.0
    with pytest.raises(InputError, match="2 revolutions"):
        synchronous_deviation_ratio(rec[:1], base)
    with pytest.raises(InputError, match="reference"):
        synchronous_deviation_ratio(rec, base[:10])
    with pytest.raises(InputError, match="2 whole revolutions"):
        revolution_blocks(np.ones(300), 256)


def test_line_family_concentration():
    """An increase on the BPFO comb (order 4.6, harmonics to 40) concentrates there; a flat
    increase gives concentration ≈ 1 to every line, including the dense cage comb (0.4)."""
    o = np.arange(0, 50, 0.05)
    base = [np.ones_like(o), np.ones_like(o)]
    comb = np.ones_like(o)
    for k in range(1, 11):
        comb[np.argmin(np.abs(o - 4.6 * k))] += 5.0
    lines = {("b", "BPFO"): 4.6, ("b", "BPFI"): 7.3, ("b", "FTF"): 0.4}
    got = {s.line: s for s in line_family_shares(o, comb, base, lines)}
    assert got["BPFO"].share == pytest.approx(1.0)
    assert got["BPFO"].concentration > 20
    assert got["BPFI"].concentration < 1.0
    flat = {s.line: s for s in line_family_shares(o, 2 * np.ones_like(o), base, lines)}
    for s in flat.values():
        assert s.concentration == pytest.approx(1.0, rel=0.05)


def test_line_family_share_ignores_a_baseline_line_that_falls_elsewhere():
    """Δ = max(0, record − baseline): a line of the baseline that falls in the record (order
    7.0, not a BPFO harmonic) takes nothing from the BPFO comb's share of the increase."""
    o = np.arange(0, 50, 0.05)
    base = np.ones_like(o)
    base[np.argmin(np.abs(o - 7.0))] += 8.0
    rec = np.ones_like(o)
    for k in range(1, 11):
        rec[np.argmin(np.abs(o - 4.6 * k))] += 2.0
    got = {s.line: s for s in line_family_shares(o, rec, [base, base],
                                                 {("b", "BPFO"): 4.6})}
    assert got["BPFO"].share == pytest.approx(1.0, abs=1e-12)



def test_streamed_statistics_equal_the_rows(tmp_path):
    """isolation_blocks(rows=False) accumulates each domain's per-order statistics revolution
    batch by batch (no record-long rows): the same OrderStats as compact() of the rows (the
    pump gearbox of benchmarks/bench_measured.py, float32 record with an analog tacho, 8 s)."""
    from benchmarks.bench_measured import CONFIG, write_record

    from geardyn.diagnosis.isolation import isolation_blocks
    from geardyn.io import read_record

    cfg_path = tmp_path / "pump.toml"
    cfg_path.write_text(CONFIG)
    cfg = geardyn.load_config(cfg_path)
    write_record(tmp_path / "rec.npy", 400_000, 1.0, seed=3)
    ds = read_record(tmp_path / "rec.npy", cfg=cfg)
    rows = isolation_blocks(ds, cfg, "acc").compact()
    stats = isolation_blocks(ds, cfg, "acc", rows=False)
    assert stats.domains == {} and set(stats.stats) == set(rows.stats) and stats.top == rows.top
    for k, a in rows.stats.items():
        b = stats.stats[k]
        assert a.n == b.n and a.mean.size == b.mean.size
        np.testing.assert_allclose(b.mean, a.mean, rtol=0, atol=1e-12 * np.abs(a.mean).max())
        np.testing.assert_allclose(b.var, a.var, rtol=0, atol=1e-12 * a.var.max())
        assert np.array_equal(stats.ambiguous[k], rows.ambiguous[k])
