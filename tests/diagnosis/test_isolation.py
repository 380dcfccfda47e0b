"""Isolation statistics against closed forms.

The synchronous deviation ratio is the F statistic of a one-way ANOVA of the revolutions: for
Gaussian noise alone its mean is ν₂/(ν₂ − 2) ≈ 1 (ν₂ = samples·(R − 1) denominator degrees of
freedom); a pattern repeated in every revolution with power P on noise of variance σ² raises it
to ≈ 1 + R·P/σ²; a pattern whose position drifts between revolutions does not.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from geardyn.diagnosis.isolation import (
    Evidence,
    isolate,
    line_family_shares,
    revolution_blocks,
    synchronous_deviation_ratio,
)
from geardyn.diagnosis.verdict import ComponentVerdict, IndicatorVerdict, Verdict
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


def _iv(value, th=1.0):
    return IndicatorVerdict(value=value, threshold=th, lower=None, mean=0.0, std=0.0,
                            sigma=0.0, n=3, margin=value / th, alarm=value > th,
                            direction="upper", channel="acc")


def test_isolation_rules():
    """1: SDR decides for rotating members; 2: wheels sharing an angle keep an alarm above half
    the largest margin; 3: a shaft yields to a toothed member turning with it."""
    comps = {
        "mid": ComponentVerdict("mid", "shaft", "alarm", {"FM4": _iv(5.0)}),
        "mid/z19": ComponentVerdict("mid/z19", "wheel", "alarm", {"SER": _iv(3.0)}),
        "mid/z71": ComponentVerdict("mid/z71", "wheel", "alarm", {"SER": _iv(2.0)}),
        "out": ComponentVerdict("out", "shaft", "alarm", {"FM4": _iv(4.0)}),
    }
    v = Verdict(machine="m", channels=["acc"], rule=None, components=comps)
    ev = {"mid": Evidence("mid", "SDR", 50.0, 1.0, 0.01, 2.0),
          "mid/z19": Evidence("mid/z19", "SDR_TE", 40.0, 1.0, 0.01, 2.0),
          "mid/z71": Evidence("mid/z71", "SDR_TE", 12.0, 1.0, 0.01, 2.0),
          "out": Evidence("out", "SDR", 1.1, 1.0, 0.01, 2.0)}
    items = [SimpleNamespace(name="mid", abs_ratio=1.0), SimpleNamespace(name="mid/z19",
             abs_ratio=1.0), SimpleNamespace(name="mid/z71", abs_ratio=1.0),
             SimpleNamespace(name="out", abs_ratio=0.3)]
    notes = isolate(v, ev, SimpleNamespace(items=items))
    assert v.alarms == ["mid/z19"]
    assert v.components["out"].state == "healthy"  # rose, but not synchronous (rule 1)
    assert "SDR" in v.components["out"].indicators
    assert any("mid/z71" in n for n in notes) and any("shaft alarm explained" in n for n in notes)


def test_isolation_planetary_stage_and_unknown():
    """Members of one planetary stage are seen through one sensor path: only those above half
    the largest margin keep an alarm; a member in detection alarm without an SDR (too few own
    revolutions) is unknown, not in alarm."""
    comps = {
        "st.sun": ComponentVerdict("st.sun", "sun", "alarm", {"FM4": _iv(3.0)}),
        "st.ring": ComponentVerdict("st.ring", "ring", "alarm", {"FM4": _iv(2.0)}),
        "st.planet1": ComponentVerdict("st.planet1", "planet", "alarm", {"FM4": _iv(2.0)}),
    }
    v = Verdict(machine="m", channels=["acc"], rule=None, components=comps)
    ev = {"st.sun": Evidence("st.sun", "SDR", 9.5, 1.0, 0.01, 2.0),
          "st.ring": Evidence("st.ring", "SDR", 2.4, 1.0, 0.01, 2.0)}
    items = [SimpleNamespace(name="st.sun", abs_ratio=0.81, stage="st"),
             SimpleNamespace(name="st.ring", abs_ratio=0.19, stage="st"),
             SimpleNamespace(name="st.planet1", abs_ratio=0.48, stage="st")]
    isolate(v, ev, SimpleNamespace(items=items))
    assert v.alarms == ["st.sun"]
    assert v.components["st.ring"].state == "healthy"
    assert v.components["st.planet1"].state == "unknown"
