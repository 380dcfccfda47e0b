"""Detection and localisation statistics (issue 18) against closed forms and hand
computations.

* Šidák level α = 1 − (1 − P)^(1/m) (Šidák 1967);
* the evidence threshold is the one-sided Student prediction bound of the log statistic
  (Hahn & Meeker 1991, ch. 4), computed here independently with scipy's t quantile;
* the coherent SDR is the mean over orders of a per-order random-effects ANOVA F ratio —
  computed here by explicit loops over orders, records and revolutions; its null mean for
  Gaussian revolutions against one baseline is E[F(2, ν)] = ν/(ν − 2) with ν the pooled
  within-run degrees of freedom, and about 1 for a new member of a fleet that varies;
* the posterior of a hypothesis with score z against one with score 0 is
  e^{z²/2}/(e^{z²/2} + 1).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.stats import t as student

from geardyn.diagnosis.isolation import (
    ARRAY_CANCELLED,
    Evidence,
    band_energy_share,
    bearing_evidence,
    bearing_line_shares,
    coherent_evidence,
    coherent_sdr,
    comb_mask,
    evidence_from_null,
    order_stats,
    planet_array_gain,
    planet_array_masks,
    synchronous_deviation_ratio,
)
from geardyn.diagnosis.localise import (
    combined_score,
    localise,
    name_planet,
    pooled_scores,
    posterior,
    sidak_alpha,
)
from geardyn.diagnosis.verdict import ComponentVerdict, IndicatorVerdict, Verdict
from geardyn.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

SPR, R = 128, 10


def test_sidak_level_closed_form():
    assert sidak_alpha(0.01, 1) == pytest.approx(0.01, rel=1e-12)
    assert sidak_alpha(0.01, 100) == pytest.approx(1 - 0.99 ** 0.01, rel=1e-10)
    assert 1 - (1 - sidak_alpha(0.05, 37)) ** 37 == pytest.approx(0.05, rel=1e-10)
    with pytest.raises(InputError, match="false_alarm_probability"):
        sidak_alpha(1.5, 3)


def test_evidence_threshold_is_the_student_prediction_bound_and_rises_with_the_spread():
    null = [1.0, 1.3, 0.8, 1.1, 0.9]
    ev = evidence_from_null("c", "cSDR", 5.0, null, alpha=1e-3)
    lg = np.log(null)
    n = len(null)
    bound = math.exp(lg.mean() + student.isf(1e-3, n - 1) * lg.std(ddof=1) * math.sqrt(1 + 1 / n))
    assert ev.threshold == pytest.approx(bound, rel=1e-12)
    z = (math.log(5.0) - lg.mean()) / (lg.std(ddof=1) * math.sqrt(1 + 1 / n))
    assert ev.z == pytest.approx(z, rel=1e-12)
    assert ev.p == pytest.approx(student.sf(z, n - 1), rel=1e-10)
    assert ev.passed == (bound < 5.0) and ev.margin == pytest.approx(5.0 / bound)
    wider = evidence_from_null("c", "cSDR", 5.0, [1.0, 2.0, 0.5, 1.6, 0.6], alpha=1e-3)
    assert wider.threshold > ev.threshold  # a wider healthy ensemble raises the threshold
    assert not math.isfinite(evidence_from_null("c", "cSDR", 5.0, [1.0], 1e-3).threshold)


def _coherent_by_loops(rec, bases):
    """Independent random-effects ANOVA per order: explicit loops over orders, members and
    revolutions (Searle, Casella & McCulloch 1992, ch. 3), the record's mean against its own
    within-record variance (Welch 1947)."""
    def spec(rows):
        n = rows.shape[1]
        k = np.arange(n // 2 + 1)
        th = 2 * np.pi * np.outer(np.arange(n), k) / n
        return (rows @ (np.cos(th) - 1j * np.sin(th))) / n
    rs, bs = spec(rec), [spec(b) for b in bases]
    m = len(bs)
    fs = []
    for o in range(1, rs.shape[1]):
        means = [b[:, o].mean() for b in bs]
        grand = sum(means) / m
        ss = sum(np.sum(np.abs(b[:, o] - b[:, o].mean()) ** 2) for b in bs)
        v = ss / sum(b.shape[0] - 1 for b in bs)  # the baselines' pooled within variance
        v_rec = np.sum(np.abs(rs[:, o] - rs[:, o].mean()) ** 2) / (rs.shape[0] - 1)
        inv_n = sum(1 / b.shape[0] for b in bs) / m
        between = 0.0
        if m > 1:
            between = max(sum(abs(x - grand) ** 2 for x in means) / (m - 1) - v * inv_n, 0.0)
        if v + v_rec > 0:  # the record's mean judged by its own spread (Welch 1947)
            fs.append(abs(rs[:, o].mean() - grand) ** 2
                      / (between * (1 + 1 / m) + v_rec / rs.shape[0] + v * inv_n / m))
    return float(np.mean(fs))


def _noise(seed, r=R):
    return np.random.default_rng(seed).normal(0.0, 1.0, (r, SPR))


def test_coherent_sdr_against_explicit_loops_and_its_null_mean():
    bases = [_noise(s) for s in range(3)]
    rec = _noise(9)
    got = coherent_sdr(order_stats(rec), [order_stats(b) for b in bases])
    assert got == pytest.approx(_coherent_by_loops(rec, bases), rel=1e-9)
    one = coherent_sdr(order_stats(rec), [order_stats(bases[0])])
    assert one == pytest.approx(_coherent_by_loops(rec, bases[:1]), rel=1e-9)
    # null with one baseline (fixed effects): F_o ~ F(2, ν), ν = 2·2·(R − 1) real pooled dof
    # per order: E = ν/(ν − 2)
    vals = [coherent_sdr(order_stats(_noise(100 + s)), [order_stats(_noise(200 + s))])
            for s in range(60)]
    nu = 2 * 2 * (R - 1)
    assert np.mean(vals) == pytest.approx(nu / (nu - 2), abs=0.05)
    # several baselines without any between-record effect: the estimated σ_b² ≥ 0 only adds
    # to the denominator, so the mean stays at or below the fixed-effects value
    vals = [coherent_sdr(order_stats(_noise(100 + s)), [order_stats(_noise(200 + 3 * s + j))
                                                       for j in range(3)]) for s in range(60)]
    nu = 2 * 4 * (R - 1)
    assert 0.6 < np.mean(vals) < nu / (nu - 2) + 0.02


def test_coherent_sdr_a_healthy_fleet_that_varies_is_no_evidence():
    """Healthy machines differ (speed, load, transfer path): each record carries its own
    synchronous pattern, here a Gaussian one of power 4× the noise per order. A new machine of
    the same fleet scores E[F_o] = 1 against the random-effects denominator (with σ_b² and V
    estimated from M = 12 records the mean rises to about E[1/χ²_ν/ν] for ν ≈ 2(M − 1): 1.1),
    while the fixed-effects test of one record against another counts the fleet's spread as
    evidence: per order E ≈ (2·4V + 2V/R)/(2V/R) = 4R + 1 = 41."""
    def machine(seed):
        rng = np.random.default_rng(seed)
        pattern = 2.0 * rng.normal(0.0, 1.0, SPR)  # synchronous: repeats every revolution
        return rng.normal(0.0, 1.0, (R, SPR)) + pattern

    fleet = [order_stats(machine(s)) for s in range(12)]
    new = [coherent_sdr(order_stats(machine(100 + i)), fleet) for i in range(20)]
    assert 0.85 < np.mean(new) < 1.3
    fixed = [coherent_sdr(order_stats(machine(100 + i)), [fleet[i % 12]]) for i in range(20)]
    assert np.mean(fixed) > 5.0


def test_coherent_sdr_a_strong_line_that_does_not_repeat_is_bounded_by_its_leak():
    """A fault of another member puts a line between this domain's orders (order 10.37 here,
    continuous across revolutions). Averaged over R revolutions it keeps the Dirichlet
    fraction |D_R(δ)|² of its power in the record's mean and spreads the rest over the
    revolutions, so judged by the record's own spread (Welch 1947) it scores at most
    R·|D|²/(1 − |D|²) at its nearest orders — 0.078 here — whatever its power, and
    its leakage raises the record's spread at the other orders: cSDR does not rise above the
    line-free value even 100 × above the noise. Judged by a variance pooled with the 12
    healthy baselines it rose by 40 % (0.86 → 1.22). A line that repeats with the member
    (order 10) rises as its power."""
    t = np.arange(R * SPR) / SPR
    bases = [order_stats(_noise(s)) for s in range(12)]

    def score(a, order):
        rec = _noise(99) + (a * np.cos(2 * np.pi * order * t)).reshape(R, SPR)
        return coherent_sdr(order_stats(rec), bases)

    for delta in (0.37, 0.63):
        d2 = (np.sin(np.pi * R * delta) / (R * np.sin(np.pi * delta))) ** 2
        assert R * d2 / (1 - d2) < 0.2
    free = score(0.0, 10.37)
    assert score(10.0, 10.37) <= free and score(100.0, 10.37) <= free
    assert score(10.0, 10.0) > 100.0 * free


def test_planet_array_gain_closed_form_and_the_sun_pattern_it_describes():
    """|Σ_n exp(−i·o·ψ_n)|/N: 1 at multiples of N and 0 elsewhere for equally spaced planets;
    a pattern repeated at each planet position (a sun tooth meeting N planets, McFadden 1991)
    has power only at the orders where the gain is not 0."""
    for n in (3, 4, 5):
        psi = 2 * np.pi * np.arange(n) / n
        g = planet_array_gain(psi, 40)
        o = np.arange(41)
        assert np.allclose(g[o % n == 0], 1.0, atol=1e-12)
        assert np.all(g[o % n != 0] < 1e-12)
        theta = 2 * np.pi * np.arange(512) / 512
        pulse = sum(np.exp(-0.5 * ((np.angle(np.exp(1j * (theta - p)))) / 0.03) ** 2)
                    for p in psi)
        spec = np.abs(np.fft.rfft(pulse)[:41]) ** 2
        assert spec[o % n != 0].max() < 1e-20 * spec.sum()
    uneven = np.radians([0.0, 118.0, 242.0])
    g = planet_array_gain(uneven, 10)
    ref = np.abs(np.exp(-1j * np.outer(np.arange(11), uneven)).sum(axis=1)) / 3
    assert np.allclose(g, ref, rtol=1e-14)
    assert np.all(g > ARRAY_CANCELLED)  # no order cancels exactly: every order kept


def test_planet_array_masks_only_for_domains_of_the_sun_or_the_ring_alone():
    import geardyn
    from geardyn.diagnosis.components import machine_components

    cfg = geardyn.load_config(EXAMPLES / "planet_crack_4_planets.toml")
    comps = machine_components(cfg, "sun")
    st = comps.planetary[0]
    of = {c.name: f"{c.abs_ratio:.12g}|{c.kind}" for c in comps.items
          if c.kind in ("sun", "ring", "planet", "shaft")}
    masks = planet_array_masks(comps, of)
    sun = next(c.name for c in comps.items if c.kind == "sun")
    ring = next(c.name for c in comps.items if c.kind == "ring")
    assert set(masks) == {of[sun], of[ring]}
    keep = masks[of[sun]](20)
    assert np.array_equal(keep, np.arange(21) % st.n_planets == 0)
    shared = {**of, "extra shaft": of[sun]}  # a domain the sun shares keeps every order
    assert of[sun] not in planet_array_masks(comps, shared)


def _coloured(seed):
    """Gaussian revolutions whose orders 40–50 are 15× stronger (a housing mode excited by
    content that does not repeat with the member)."""
    x = np.random.default_rng(seed).normal(0.0, 1.0, R * SPR)
    spec = np.fft.rfft(x)
    f = np.fft.rfftfreq(x.size, 1.0 / SPR)
    spec *= np.where((f > 40) & (f < 50), 15.0, 1.0)
    return np.fft.irfft(spec, x.size).reshape(R, SPR)


def test_coherent_sdr_weighs_what_repeats_not_what_is_strong():
    """A local pattern repeated every revolution doubles cSDR over its healthy value whether
    or not a band of strong non-synchronous content (a resonance) sits elsewhere: each order
    is judged against its own spread. The whole-band SDR is swamped by that band (its
    denominator) and moves by a few per cent only."""
    theta = 2 * np.pi * np.arange(SPR) / SPR
    pulse = 3.0 * np.exp(-0.5 * ((theta - 2.0) / 0.05) ** 2)
    for make in (_noise, _coloured):
        bases = [make(s) for s in range(3)]
        st = [order_stats(b) for b in bases]
        ref = np.mean(np.concatenate(bases), axis=0)
        coh = np.mean([coherent_sdr(order_stats(make(20 + i) + pulse), st)
                       / coherent_sdr(order_stats(make(40 + i)), st) for i in range(10)])
        whole = np.mean([synchronous_deviation_ratio(make(20 + i) + pulse, ref)
                         / synchronous_deviation_ratio(make(40 + i), ref) for i in range(10)])
        assert coh > 1.8
        if make is _coloured:
            assert whole < 1.3


def test_coherent_evidence_leave_one_out_never_includes_the_record_or_the_member():
    bases = [order_stats(_noise(s)) for s in range(4)]
    rec1 = order_stats(_noise(50) + 3.0)
    rec2 = order_stats(_noise(51))
    e1 = coherent_evidence("c", "cSDR", rec1, bases, 1e-3)
    e2 = coherent_evidence("c", "cSDR", rec2, bases, 1e-3)
    assert e1.null == e2.null  # the record is in no member's reference
    for i, b in enumerate(bases):
        others = [o for j, o in enumerate(bases) if j != i]
        assert e1.null[i] == pytest.approx(coherent_sdr(b, others), rel=1e-12)
        assert e1.null[i] != pytest.approx(coherent_sdr(b, bases), rel=1e-3)


def test_comb_bins_and_coverage():
    """Every harmonic k·f sits on bin round(k·f/Δ) with one bin either side: 3 bins per
    harmonic while harmonics do not overlap, none elsewhere."""
    o = np.arange(0, 40, 0.1)
    f = 4.63
    mask = comb_mask(o, f, 40.0)
    centres = [int(round(k * f / 0.1)) for k in range(1, 9)]
    assert mask.sum() == 3 * len(centres)
    for i in centres:
        assert mask[i - 1] and mask[i] and mask[i + 1]
        assert not mask[i - 2] and not mask[min(i + 2, o.size - 1)]


def test_band_energy_share_rises_with_the_fault_lines_only():
    o = np.arange(0, 40, 0.1)
    base = np.ones_like(o)
    rec = base.copy()
    for k in range(1, 8):
        rec[int(round(k * 4.63 / 0.1))] += 3.0
    assert band_energy_share(o, rec, 4.63) > 3 * band_energy_share(o, base, 4.63)
    # a line of the baseline falling elsewhere does not lower the comb's own energy
    fallen = rec.copy()
    fallen[int(round(7.0 / 0.1))] = 0.0
    assert band_energy_share(o, fallen, 4.63) >= band_energy_share(o, rec, 4.63)


def test_bearing_line_shares_leave_out_the_bins_another_bearing_shares():
    """Bearing A's BPFO at order 3.0 spalled (strong comb), bearing B's BPFO at 4.5: their
    combs meet at 9, 18, 27, 36. B's share without A's bins stays at its healthy value
    however strong A's comb, while with them it rises; an identical bearing C (same line as
    B) is the same hypothesis and keeps every bin of its comb; A's own share rises."""
    o = np.arange(0, 40, 0.1)
    healthy = np.ones_like(o)
    spalled = healthy.copy()
    for k in range(1, 14):
        spalled[int(round(k * 3.0 / 0.1))] += 30.0
    bearings = [SimpleNamespace(name=n, fault_orders={"BPFO": f})
                for n, f in (("A", 3.0), ("B", 4.5), ("C", 4.5))]
    h = bearing_line_shares(o, healthy, bearings)
    f = bearing_line_shares(o, spalled, bearings)
    assert f[("A", "BPFO")] > 5 * h[("A", "BPFO")]
    total_h, total_f = np.sum(healthy**2), np.sum(spalled**2)
    assert f[("B", "BPFO")] == pytest.approx(h[("B", "BPFO")] * total_h / total_f, rel=1e-12)
    assert band_energy_share(o, spalled, 4.5) > 4 * band_energy_share(o, healthy, 4.5)
    assert f[("C", "BPFO")] == f[("B", "BPFO")]
    shared = comb_mask(o, 3.0, o[-1])
    assert np.isclose(h[("B", "BPFO")] * total_h,
                      np.sum(healthy[comb_mask(o, 4.5, o[-1]) & ~shared] ** 2))


def _ses(values):
    import xarray as xr

    return xr.DataArray(values, dims="order", coords={"order": np.arange(0, 40, 0.1)})


def test_bearing_evidence_compares_the_whole_band_spectra_of_every_run():
    """Each run's kurtogram picks its own envelope band; on healthy runs the shares in those
    bands spread over decades (here 1e-9 … 1e-1 of BPFO 4.63), so a spalled record's share
    cannot pass. The whole-band spectrum (``bearing_spectrum``), the same definition in every
    run, gives a tight null and the spall passes; when one run lacks it, every run falls
    back to its ``envelope_spectrum`` (never a mix)."""
    o = np.arange(0, 40, 0.1)
    comb = comb_mask(o, 4.63, o[-1])
    comps = SimpleNamespace(bearings=[SimpleNamespace(name="out", fault_orders={"BPFO": 4.63})])
    rng = np.random.default_rng(5)

    def run(share_scale, spall):
        whole = 1.0 + 0.05 * rng.standard_normal(o.size)
        whole[comb] += 3.0 if spall else 0.0
        band = np.ones(o.size)
        band[comb] = share_scale
        return SimpleNamespace(envelope_spectrum=_ses(band), bearing_spectrum=_ses(whole),
                               components=comps)

    base = [run(10.0 ** -k, False) for k in (1, 3, 5, 7, 9, 2)]
    rec = run(1.0, True)
    ev = bearing_evidence(base, rec, 1e-3)["out"]
    assert ev.passed and ev.measure == "BPFO band energy"
    mixed = [*base[:-1], SimpleNamespace(envelope_spectrum=base[-1].envelope_spectrum,
                                         bearing_spectrum=None, components=comps)]
    fallback = bearing_evidence(mixed, rec, 1e-3)["out"]
    assert not fallback.passed and fallback.threshold > 1e3 * ev.threshold


def test_pooled_scores_pool_one_bearing_line_over_the_bearings_not_every_line():
    """The posterior's scores pool the log-spread over evidence of one statistic: the BPFO
    share of a bearing is not scaled by the wide spread of another bearing's cage-line
    share, while cSDR domains still pool together."""
    bpfo = Evidence("a", "BPFO band energy", 2.0, 1.0, 0.1, 1.5, z=0.0, n=6)
    ftf = Evidence("b", "FTF band energy", 2.0, 1.0, 3.0, 50.0, z=0.0, n=6)
    c1 = Evidence("s", "cSDR", 2.0, 1.0, 0.2, 1.5, z=0.0, n=6)
    c2 = Evidence("p", "cSDR_TE", 2.0, 1.0, 0.4, 1.5, z=0.0, n=6)
    score = pooled_scores([bpfo, ftf, c1, c2])
    k = math.sqrt(1 + 1 / 6)
    assert score(bpfo) == pytest.approx(math.log(2.0) / (0.1 * k))
    assert score(ftf) == pytest.approx(math.log(2.0) / (3.0 * k))
    sp = math.sqrt((0.2**2 + 0.4**2) / 2)
    assert score(c1) == pytest.approx(math.log(2.0) / (sp * k)) == score(c2)


def test_posterior_closed_form():
    p = posterior({"a": 3.0, "b": 0.0})
    assert p["a"] == pytest.approx(math.exp(4.5) / (math.exp(4.5) + 1), rel=1e-12)
    assert posterior({"a": -2.0, "b": float("nan")}) == {"a": 0.5, "b": 0.5}


def _iv(value, th=1.0):
    return IndicatorVerdict(value=value, threshold=th, lower=None, mean=0.0, std=0.0,
                            sigma=0.0, n=3, margin=value / th, alarm=value > th,
                            direction="upper", channel="acc")


def _ev(comp, measure, value, z, group=None, threshold=2.0):
    return Evidence(comp, measure, value, 1.0, 0.1, threshold, z=z, p=0.0, n=6,
                    group=group or comp)


def _verdict(states):
    comps = {n: ComponentVerdict(n, k, "unknown", {"FM4": _iv(m)}) for n, (k, m) in
             states.items()}
    return Verdict(machine="m", channels=["acc"], rule=None, components=comps)


def _items(spec):
    return SimpleNamespace(items=[SimpleNamespace(name=n, abs_ratio=r, stage=st)
                                  for n, (r, st) in spec.items()])


def _run(v, ev, items):
    return localise(v, ev, items, alpha=1e-3, false_alarm_probability=0.01, tests=10)


def test_detected_but_unlocalised_is_uncertain_never_healthy():
    """A detection indicator above its threshold with no isolation evidence that separates
    the candidates: machine ``uncertain``, the candidates listed, no component healthy among
    those that alarmed."""
    v = _verdict({"a": ("wheel", 3.0), "b": ("wheel", 0.5)})
    ev = {"a": _ev("a", "cSDR", 1.0, 0.4), "b": _ev("b", "cSDR", 1.0, 0.5)}
    _run(v, ev, _items({"a": (1.0, None), "b": (2.0, None)}))
    assert v.state == "uncertain"
    assert v.summary()["verdict"] == "uncertain" and v.summary()["detected"]
    assert v.components["a"].state == "uncertain"
    assert set(v.summary()["candidates"]) >= {"a"}
    assert v.localisation["state"] == "uncertain"


def test_a_location_needs_evidence_above_its_threshold():
    """The largest posterior is not enough: evidence below its threshold at the localisation
    level leaves the location uncertain. Null: geometric mean 1, log-spread 0.1, n = 6; with
    G = 2 hypotheses at confidence 0.95 the level is 1 − 0.95^(1/2) = 0.0253 and the bound
    exp(t_5(1 − 0.0253)·0.1·√(7/6)) = 1.32 (scipy's t below)."""
    from scipy.stats import t as tdist

    bound = math.exp(tdist.isf(1 - 0.95**0.5, 5) * 0.1 * math.sqrt(7 / 6))
    assert _ev("a", "cSDR", 1.0, 0.0).bound(1 - 0.95**0.5) == pytest.approx(bound, rel=1e-12)
    v = _verdict({"a": ("wheel", 3.0), "b": ("wheel", 0.5)})
    ev = {"a": _ev("a", "cSDR", 0.99 * bound, 6.0), "b": _ev("b", "cSDR", 1.0, 0.0)}
    _run(v, ev, _items({"a": (1.0, None), "b": (2.0, None)}))
    assert v.localisation["state"] == "uncertain" and v.state == "uncertain"
    v2 = _verdict({"a": ("wheel", 3.0), "b": ("wheel", 0.5)})
    _run(v2, {"a": _ev("a", "cSDR", 1.01 * bound, 6.0), "b": _ev("b", "cSDR", 1.0, 0.0)},
         _items({"a": (1.0, None), "b": (2.0, None)}))
    assert v2.location == ["a"]


def test_a_bearing_outweighs_the_wheels_of_its_shaft():
    """Detection alarms on a bearing and both wheels of its shaft; the bearing's fault-band
    energy is far out of its null, the wheels' coherent SDR of their own meshes is not: the
    bearing is the location, the wheels are explained."""
    v = _verdict({"brg": ("bearing", 2.0), "s/z42": ("wheel", 3.8), "s/z53": ("wheel", 7.4)})
    ev = {"brg": _ev("brg", "BPFO band energy", 30.0, 12.0),
          "s/z42": _ev("s/z42", "cSDR_TE", 2.5, 2.4),
          "s/z53": _ev("s/z53", "cSDR_TE", 2.7, 2.6)}
    _run(v, ev, _items({"brg": (0.0, None), "s/z42": (1.0, None), "s/z53": (1.0, None)}))
    assert v.state == "alarm" and v.location == ["brg"]
    assert v.alarms == ["brg"]
    assert v.components["s/z42"].state == v.components["s/z53"].state == "healthy"
    assert v.localisation["confidence"] > 0.95


def test_shaft_yields_and_planet_set_and_named_planet():
    v = _verdict({"car": ("shaft", 0.5), "st.ring": ("ring", 0.5),
                  "st.p1": ("planet", 2.0), "st.p2": ("planet", 2.0), "st.p3": ("planet", 2.0)})
    ev = {"car": _ev("car", "cSDR", 9.0, 9.0),
          "st.ring": _ev("st.ring", "cSDR", 3.0, 3.0),
          **{f"st.p{i}": _ev(f"st.p{i}", "cSDR", 12.0, 11.0, group="planets") for i in (1, 2, 3)}}
    items = _items({"car": (0.2, None), "st.ring": (0.2, "st"), "st.p1": (0.5, "st"),
                    "st.p2": (0.5, "st"), "st.p3": (0.5, "st")})
    v1 = _verdict({k: (c.kind, c.indicators["FM4"].value) for k, c in v.components.items()})
    _run(v, dict(ev), items)
    assert v.localisation["level"] == "planet set"
    assert set(v.location) == {"st.p1", "st.p2", "st.p3"}
    assert any("yields to st.ring" in n for n in v.notes)
    v2 = _verdict({k: (c.kind, c.indicators["FM4"].value) for k, c in v.components.items()})
    # planet-separated evidence names planet 2: its per-order deviation is 1.5× the others'
    rng = np.random.default_rng(7)
    planet_ev = {f"st.p{i}#planet": _planet_ev(f"st.p{i}", scale, rng)
                 for i, scale in ((1, 1.0), (2, 1.5), (3, 1.0))}
    _run(v1, {**ev, **planet_ev}, items)
    assert v1.location == ["st.p2"] and v1.localisation["level"] == "planet"
    assert v1.components["st.p1"].state == "healthy"
    # every planet's deviation alike (a change the planet windows share): the set stays
    same = {f"st.p{i}#planet": _planet_ev(f"st.p{i}", 1.0, rng) for i in (1, 2, 3)}
    _run(v2, {**ev, **same}, items)
    assert v2.localisation["level"] == "planet set"


K_ORDERS = 2000


def _planet_ev(comp, scale, rng, offset=1.0, members=6):
    """Planet-separated evidence with per-order deviations: noise power D·χ²₂/2 per order
    (D varying over the orders like a spectrum), × ``offset`` for this planet's window in
    every record (a fixed window-to-window difference), × ``scale`` in the record only."""
    d = np.exp(np.linspace(0.0, -4.0, K_ORDERS))

    def draw():
        return d * offset * rng.exponential(1.0, K_ORDERS)

    return replace(_ev(comp, "cSDR_planet", 1.0, 3.0, group=comp), deviation=scale * draw(),
                   null_deviation=tuple(draw() for _ in range(members)),
                   null_runs=tuple(range(members)))


def test_name_planet_compares_per_order_log_ratios_with_the_healthy_spread():
    """p of planet a against b: Student prediction p-value of the record's median over the
    orders of log(d_a/d_b) against the same median of each healthy member (Hahn & Meeker
    1991, ch. 4), computed here independently; named iff every p ≤ (1 − confidence)/N."""
    from scipy.stats import t as student

    rng = np.random.default_rng(3)
    for scale, named in ((1.0, False), (1.4, True)):
        ev = {c: _planet_ev(c, scale if c == "a" else 1.0, rng) for c in "abc"}
        got, p = name_planet(ev, 0.95)
        ps = []
        for o in "bc":
            med = float(np.median(np.log(ev["a"].deviation / ev[o].deviation)))
            null = np.array([np.median(np.log(x / y)) for x, y in
                             zip(ev["a"].null_deviation, ev[o].null_deviation, strict=True)])
            sd = null.std(ddof=1) * np.sqrt(1.0 + 1.0 / null.size)
            ps.append(float(student.sf((med - null.mean()) / sd, null.size - 1)))
        assert (got == "a") is named
        if named:
            assert p == pytest.approx(max(ps), rel=1e-9) and p <= 0.05 / 3
        else:
            assert got is None and p > 0.05 / 3
    # a planet whose window always shows 20 % more noise is not named: the healthy members
    # carry the same offset
    ev = {c: _planet_ev(c, 1.0, rng, offset=1.2 if c == "a" else 1.0) for c in "abc"}
    assert name_planet(ev, 0.95)[0] is None
    # no healthy spread to compare with: nothing named
    ev = {c: replace(_planet_ev(c, 2.0 if c == "a" else 1.0, rng), null_deviation=())
          for c in "abc"}
    assert name_planet(ev, 0.95) == (None, pytest.approx(np.nan, nan_ok=True))


def test_nothing_detected_is_healthy():
    v = _verdict({"a": ("wheel", 0.5), "b": ("bearing", 0.7)})
    _run(v, {"a": _ev("a", "cSDR", 1.0, 0.2)}, _items({"a": (1.0, None), "b": (0.0, None)}))
    assert v.state == "healthy" and v.localisation["state"] == "none"
    assert {c.state for c in v.components.values()} == {"healthy"}


def test_leave_one_out_leaves_the_whole_dynamic_run_out():
    """Two measurements of one dynamic run are near-copies: a member's null value must not
    use its twin as reference (it would make the null, and so the threshold, too small)."""
    runs = [0, 0, 1, 1, 2, 2]
    dyn = {r: _noise(300 + r) for r in set(runs)}
    bases = [order_stats(dyn[r] + 0.01 * _noise(400 + i)) for i, r in enumerate(runs)]
    e = coherent_evidence("c", "cSDR", order_stats(_noise(9)), bases, 1e-3, runs=runs)
    for i in range(len(bases)):
        others = [b for j, b in enumerate(bases) if runs[j] != runs[i]]
        assert e.null[i] == pytest.approx(coherent_sdr(bases[i], others), rel=1e-12)
    naive = coherent_evidence("c", "cSDR", order_stats(_noise(9)), bases, 1e-3)
    assert np.mean(naive.null) < 0.7 * np.mean(e.null)


def test_combined_score_is_the_sidak_adjusted_best():
    """z of the best of k scores with p = 1 − (1 − Φ(−z_max))^k (Šidák 1967), computed here
    with scipy's normal law; continuous across the small-p branches."""
    from scipy.stats import norm

    assert combined_score([2.5]) == 2.5
    for zs in ([3.0, 1.0, -0.5], [4.0, 4.0], [6.0, 2.0, 2.0, 2.0, 2.0]):
        p = -math.expm1(len(zs) * math.log1p(-norm.sf(max(zs))))  # 1 − (1 − p₁)^k
        assert combined_score(zs) == pytest.approx(norm.isf(p), rel=1e-9)
    assert combined_score([3.0, float("nan")]) == 3.0
    assert math.isnan(combined_score([float("nan")]))
    # far tail: k·p; beyond exp's range the asymptotic inverse, both close to z − ln(k)/z
    for z in (12.0, 30.0, 50.0):
        got = combined_score([z, 0.0, 0.0])
        assert got < z and got == pytest.approx(z - math.log(3.0) / z, abs=0.01)


def test_ambiguous_orders_against_a_brute_force_search():
    """Order o of a domain turning a times per reference revolution is ambiguous when some
    harmonic k·r of another member lies within the TSA main lobe |k·r/a − o| < 1/n; the member
    itself (r = a) never is."""
    from geardyn.diagnosis.isolation import ambiguous_orders

    rng = np.random.default_rng(7)
    for _ in range(20):
        a = float(rng.uniform(0.2, 2.0))
        ratios = [a, *rng.uniform(0.05, 3.0, 3)]
        n, top = int(rng.integers(2, 30)), int(rng.integers(20, 200))
        got = ambiguous_orders(a, ratios, n, top)
        want = np.zeros(top + 1, bool)
        for o in range(1, top + 1):
            for r in ratios[1:]:
                ks = np.arange(1, int((o + 1) * a / r) + 2)
                if np.any(np.abs(ks * r / a - o) < 1.0 / n):
                    want[o] = True
        assert np.array_equal(got, want)
    # a member at half the rate reaches every order of the domain
    assert ambiguous_orders(1.0, [1.0, 0.5], 10, 10)[1:].all()
    assert not ambiguous_orders(1.0, [1.0], 10, 10).any()


def test_a_shaft_yields_to_the_sun_wheel_it_carries():
    """The input shaft of a planetary stage turns at its absolute rate, its sun wheel at the
    rate relative to the carrier: different rates, one link. A passing sun-wheel evidence takes
    the shaft's hypothesis over."""
    v = _verdict({"in": ("shaft", 0.5), "st.sun": ("sun", 2.0), "x": ("wheel", 0.5)})
    ev = {"in": _ev("in", "cSDR", 9.0, 7.0), "st.sun": _ev("st.sun", "cSDR", 3.0, 4.0),
          "x": _ev("x", "cSDR", 1.0, 0.0)}
    items = SimpleNamespace(items=[SimpleNamespace(name="in", abs_ratio=1.0, stage=None,
                                                   link="sun_shaft"),
                                   SimpleNamespace(name="st.sun", abs_ratio=0.8, stage="st",
                                                   link="sun_shaft"),
                                   SimpleNamespace(name="x", abs_ratio=2.0, stage=None,
                                                   link="other")])
    _run(v, ev, items)
    assert v.location == ["st.sun"]
    assert any("in: shaft evidence yields to st.sun" in n for n in v.notes)


def test_pooled_scores_by_hand():
    """z = log(value/mean)/(s_p·√(1 + 1/n)), s_p² = Σ(n−1)s²/Σ(n−1) per evidence kind: a domain
    whose few baseline runs happened to agree (small s) does not outrank a larger change."""
    from geardyn.diagnosis.localise import pooled_scores

    def ev(measure, value, mean, std, n):
        return Evidence("c", measure, value, mean, std, 1.0, z=99.0, n=n)

    tight = ev("cSDR", 15.0, 1.0, 0.1, 12)    # 15× its mean, own z = 25.9
    wide = ev("cSDR", 30.0, 1.0, 0.7, 6)      # 30× its mean, own z = 4.5
    band = ev("BPFO band energy", 4.0, 2.0, 0.2, 12)
    score = pooled_scores([tight, wide, band])
    sp = math.sqrt((11 * 0.1**2 + 5 * 0.7**2) / 16)
    assert score(tight) == pytest.approx(math.log(15.0) / (sp * math.sqrt(13 / 12)))
    assert score(wide) == pytest.approx(math.log(30.0) / (sp * math.sqrt(7 / 6)))
    assert score(wide) > score(tight)
    assert score(band) == pytest.approx(math.log(2.0) / (0.2 * math.sqrt(13 / 12)))
