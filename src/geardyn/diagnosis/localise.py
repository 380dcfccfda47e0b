"""Detection and localisation: two answers of one verdict.

**Detection** (the machine): is the record outside the healthy population? Every judged
detection indicator of every component (μ + k·σ over the baseline ensemble,
:mod:`geardyn.diagnosis.baseline`) and every isolation statistic (:mod:`geardyn.diagnosis.
isolation`) is one test. With m tests and a stated machine false-alarm probability P, each test
runs at the Šidák level

    α = 1 − (1 − P)^(1/m)                                   (Šidák 1967)

so that a healthy record raises any alarm with probability at most P when the tests are
independent, and less when they are positively correlated (indicators of one signal are); the
detection threshold factor is k = Φ⁻¹(1 − α). The machine is *detected* when any test
passes. A detection is never reported healthy: isolation decides *where*, not *whether*.

**Localisation** (the component): which hypothesis explains the change? Each signal domain
whose evidence exists is one hypothesis — a component, or the components that domain cannot
tell apart (the planets of a stage in their common own angle; a shaft and the wheels on it
without transmission-error channels). Each hypothesis h has a standardised score z_h of its
evidence against its own null sample, ``(log value − μ)/(s·√(1 + 1/n))`` over the baseline
members (:func:`geardyn.diagnosis.isolation.evidence_from_null`), and a generalised likelihood
ratio Λ_h = exp(½·max(z_h, 0)²) (the maximum-likelihood mean shift of a unit-variance Gaussian
score against no shift). With a uniform prior over
the hypotheses (single fault), the **posterior** is

    P(h | record) = Λ_h / Σ_g Λ_g.

The record is *localised* to h when P(h) ≥ the stated confidence (default 0.95), otherwise
the location is *uncertain* and the candidates are the most probable hypotheses whose
posteriors add up to the confidence. A shaft hypothesis yields to a toothed member turning
with it whose evidence passes its threshold (the member is the more specific explanation of
the same synchronous change). A planet set (the planets' common domain) is refined by the
planet-separated evidence (McFadden 1991 windows): a planet is named when its rows' deviation
exceeds every other planet's, order by order, beyond what the healthy members show between
the same planets (:func:`name_planet`), else the location is the planet set.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from geardyn.diagnosis.isolation import ROTATING, Evidence
from geardyn.errors import InputError

TOOTHED = ("wheel", "sun", "ring", "planet")


def sidak_alpha(false_alarm_probability: float, tests: int) -> float:
    """Per-test level α = 1 − (1 − P)^(1/m) (Šidák 1967) for a family false-alarm
    probability P over m tests."""
    p = float(false_alarm_probability)
    if not (math.isfinite(p) and 0.0 < p < 1.0):
        raise InputError(f"false_alarm_probability: must be in (0, 1), got {p!r}")
    m = max(int(tests), 1)
    return float(-math.expm1(math.log1p(-p) / m))


def per_test_level(false_alarm_probability: float, threshold_k: float | None, tests: int
                   ) -> tuple[float, float, float]:
    """(α per test, threshold factor k, family false-alarm probability P) over ``tests`` = m
    tests: the Šidák level α = 1 − (1 − P)^(1/m) (Šidák 1967, :func:`sidak_alpha`) and
    k = Φ⁻¹(1 − α); an explicit ``threshold_k`` overrides: α = Φ(−k), P = 1 − (1 − α)^m.
    One rule for ``geardyn diagnose`` and sweep verdicts."""
    from scipy.stats import norm

    m = max(int(tests), 1)
    if threshold_k is not None:
        k = float(threshold_k)
        alpha = float(norm.sf(k))
        return alpha, k, float(-math.expm1(m * math.log1p(-alpha)))
    alpha = sidak_alpha(false_alarm_probability, m)
    return alpha, float(norm.isf(alpha)), float(false_alarm_probability)


def posterior(scores: Mapping[str, float]) -> dict[str, float]:
    """Posterior of each hypothesis from its standardised score z (uniform prior,
    likelihood ratio exp(½·max(z, 0)²)); non-finite scores count as z = 0."""
    if not scores:
        return {}
    ll = {h: 0.5 * max(z, 0.0) ** 2 if math.isfinite(z) else 0.0 for h, z in scores.items()}
    top = max(ll.values())
    w = {h: math.exp(v - top) for h, v in ll.items()}
    total = sum(w.values())
    return {h: v / total for h, v in w.items()}


def _credible(post: Mapping[str, float], confidence: float) -> list[str]:
    """The most probable hypotheses whose posteriors add up to ``confidence``."""
    out, acc = [], 0.0
    for h in sorted(post, key=post.get, reverse=True):
        out.append(h)
        acc += post[h]
        if acc >= confidence:
            break
    return out


def _add_indicator(cv: Any, ev: Evidence) -> None:
    from geardyn.diagnosis.verdict import IndicatorVerdict

    channel = next(iter(cv.indicators.values())).channel if cv.indicators else ""
    cv.indicators[ev.measure] = IndicatorVerdict(
        value=float(ev.value), threshold=float(ev.threshold), lower=None, mean=float(ev.mean),
        std=float(ev.std), sigma=float(ev.std), n=int(ev.n), margin=float(ev.margin),
        alarm=ev.passed, direction="upper", channel=channel)


def localise(verdict: Any, evidence: Mapping[str, Evidence], components: Any = None, *,
             alpha: float, false_alarm_probability: float, tests: int,
             confidence: float = 0.95) -> list[str]:
    """Set ``verdict.detection``, ``verdict.localisation`` and the component states from the
    detection indicators already judged in ``verdict`` and the isolation ``evidence``
    (component → :class:`Evidence`; planet-separated evidence under ``'<planet>#planet'``).

    States: ``alarm`` (the location), ``uncertain`` (a candidate, or a component whose
    detection indicators alarm while the location is uncertain), ``healthy`` (no alarm, or
    detection alarms explained by the location), ``unknown`` (not judged; or a rotating member
    whose detection indicators alarm but which has no evidence, when the fault is localised
    elsewhere). Returns the notes (also appended to ``verdict.notes``)."""
    from geardyn.diagnosis.verdict import is_isolation_measure

    if not 0.5 <= confidence < 1.0:
        raise InputError(f"localisation_confidence: must be in [0.5, 1), got {confidence!r}")
    comps = verdict.components
    info = {c.name: c for c in components.items} if components is not None else {}
    notes: list[str] = []
    top_ev = {c: ev for c, ev in evidence.items() if "#" not in c and c in comps}
    planet_ev = {c.split("#")[0]: ev for c, ev in evidence.items() if c.endswith("#planet")
                 and c.split("#")[0] in comps}
    for c, ev in top_ev.items():
        _add_indicator(comps[c], ev)
    for c, ev in planet_ev.items():
        _add_indicator(comps[c], ev)

    det_alarms = [(n, k, v.margin) for n, cv in comps.items() for k, v in cv.indicators.items()
                  if v.alarm and not is_isolation_measure(k)]
    ev_alarms = [(c, ev.measure, ev.margin) for c, ev in top_ev.items() if ev.passed]
    ev_alarms += [(c, ev.measure, ev.margin) for c, ev in planet_ev.items() if ev.passed]
    alarms = sorted(det_alarms + ev_alarms, key=lambda a: -a[2] if math.isfinite(a[2]) else 0)
    detected = bool(alarms)
    verdict.detection = {
        "detected": detected, "false_alarm_probability": float(false_alarm_probability),
        "tests": int(tests), "alpha_per_test": float(alpha),
        "alarms": [{"component": c, "indicator": k, "margin": m} for c, k, m in alarms]}
    alarmed = {c for c, _, _ in det_alarms}
    for c in comps.values():  # detection first: any alarm indicator or passing evidence
        if c.indicators:
            c.state = "alarm" if c.alarms else "healthy"
    if not detected:
        verdict.localisation = {"state": "none", "components": [], "confidence": None,
                                "candidates": [], "score": _SCORE}
        return notes

    # ---- hypotheses: one per evidence group
    groups: dict[str, list[str]] = {}
    for c, ev in top_ev.items():
        groups.setdefault(ev.group or c, []).append(c)
    kind = {n: cv.kind for n, cv in comps.items()}

    def ratio(n: str) -> float | None:
        c = info.get(n)
        return round(c.abs_ratio, 9) if c is not None else None

    def link(n: str) -> str | None:
        return getattr(info.get(n), "link", None) or None

    def carried(t: str, m: str) -> bool:
        """Toothed member ``t`` turns with shaft ``m``: same own rate, or on the shaft's link
        (a sun wheel on its input shaft: the wheel's angle is relative to the carrier)."""
        return (ratio(t) is not None and ratio(t) == ratio(m)) or \
            (link(t) is not None and link(t) == link(m))

    # localisation level: given a detection, each of the G hypotheses' evidence is tested at
    # the Šidák level of the localisation confidence (the chance that a healthy member's
    # evidence passes is then at most 1 − confidence over all of them)
    n_groups = max(len(groups), 1)
    alpha_loc = sidak_alpha(1.0 - confidence, n_groups)

    def passed(ev: Evidence) -> bool:
        return ev.passes_at(alpha_loc) if math.isfinite(ev.mean) else ev.passed

    passing_toothed = {c for c, ev in top_ev.items() if kind.get(c) in TOOTHED and passed(ev)}
    for g, members in list(groups.items()):
        if all(kind.get(m) == "shaft" for m in members):
            same = sorted(t for t in passing_toothed if any(carried(t, m) for m in members))
            if same:
                del groups[g]
                notes.append(f"{', '.join(members)}: shaft evidence yields to "
                             f"{', '.join(same)}, which it carries (the more specific "
                             "explanation of the change)")
    zp = pooled_scores([*top_ev.values(), *planet_ev.values()])
    scores = {g: zp(top_ev[m[0]]) for g, m in groups.items()}
    for g, members in groups.items():  # a planet set: its planets' own frames seen apart too
        seen = [zp(planet_ev[m]) for m in members if m in planet_ev]
        if seen and _one_planet_set(members, info, kind):
            scores[g] = combined_score([scores[g], *seen])
    post = posterior(scores)

    def located(g: str) -> list[str]:
        members = groups[g]
        toothed = [m for m in members if kind.get(m) in TOOTHED]
        return toothed or members

    def passes(g: str) -> bool:  # a location needs evidence above its own threshold
        return any(passed(top_ev[m]) or (m in planet_ev and passed(planet_ev[m]))
                   for m in groups[g])

    level = "component"
    if post and any(math.isfinite(z) for z in scores.values()):
        best = max(post, key=post.get)
        cand = _credible(post, confidence)
        loc: list[str] = located(best) if post[best] >= confidence and passes(best) else []
        conf = post[best] if loc else None
        if not loc:
            names = [m for g in cand for m in located(g)]
            if names and _one_planet_set(names, info, kind) and all(passes(g) for g in cand):
                loc, conf = names, sum(post[g] for g in cand)
        if loc and len(loc) > 1 and _one_planet_set(loc, info, kind):
            level = "planet set"
            sub = {p: planet_ev[p] for p in loc if p in planet_ev}
            if len(sub) == len(loc):
                p_best, p_value = name_planet(sub, confidence)
                if p_best is not None:
                    notes.append(f"planet set localised to {p_best} by the planet-separated "
                                 f"evidence (its deviation exceeds every other planet's, "
                                 f"order by order, beyond the healthy spread: p = "
                                 f"{p_value:.2g}; McFadden 1991 windows)")
                    loc, level = [p_best], "planet"
                    conf = conf * (1.0 - len(sub) * p_value)
        candidates = [{"component": m, "posterior": post[g], "evidence": top_ev[m].measure,
                       "value": top_ev[m].value, "threshold": top_ev[m].threshold}
                      for g in (cand if not loc else [best]) for m in located(g)]
    else:  # detection without isolation evidence: rank by the detection margin
        loc, conf, candidates = [], None, []
        for c, k, _m in alarms:
            if c not in [x["component"] for x in candidates]:
                candidates.append({"component": c, "posterior": None, "evidence": k,
                                   "value": comps[c].indicators[k].value,
                                   "threshold": comps[c].indicators[k].threshold})

    if loc:
        for n, cv in comps.items():
            if n in loc:
                cv.state = "alarm"
            elif cv.state == "alarm":
                if n not in top_ev and n not in planet_ev and cv.kind in ROTATING \
                        and n in alarmed:
                    cv.state = "unknown"
                    notes.append(f"{n}: detection indicators rose, but the record holds fewer "
                                 "than 2 whole revolutions of its own angle against the "
                                 "baselines, so it has no isolation evidence (state unknown; "
                                 f"the fault is localised to {', '.join(loc)})")
                else:
                    cv.state = "healthy"
                    notes.append(f"{n}: its alarms are explained by the location "
                                 f"{', '.join(loc)} (posterior {conf:.3f}; isolation)")
        state = "localised"
    else:
        names = {x["component"] for x in candidates}
        for n, cv in comps.items():
            if n in names or (cv.state == "alarm"):
                cv.state = "uncertain"
                if n not in names:
                    candidates.append({"component": n, "posterior": None,
                                       "evidence": (cv.worst or ("", 0))[0], "value": None,
                                       "threshold": None})
        notes.append("detected, location uncertain: candidates "
                     + ", ".join(x["component"] for x in candidates))
        state = "uncertain"
    verdict.localisation = {"state": state, "level": level if loc else None,
                            "components": list(loc), "confidence": conf,
                            "candidates": candidates, "score": _SCORE,
                            "alpha_per_hypothesis": alpha_loc}
    verdict.notes.extend(notes)
    return notes


_SCORE = ("posterior probability of each location hypothesis: uniform prior, likelihood "
          "ratio exp(½·max(z, 0)²) of z = log(value / healthy geometric mean) over the "
          "pooled log-spread of the record's evidence of that kind")


def pooled_scores(evidence: Sequence[Evidence]) -> Any:  # noqa: ANN401 - a function
    """Scores that compare hypotheses on one footing: ``z = log(value/mean) / (s_p·√(1 +
    1/n))`` with s_p the pooled log-spread of the record's evidence of one kind (coherent SDR
    of every domain; the fault-band energy of one bearing line — BPFO, BPFI, BSF, FTF — over
    the bearings: the lines' shares are different statistics whose spreads differ by orders of
    magnitude, the cage line's comb being the densest), s_p² = Σ (n_d − 1)·s_d² /
    Σ (n_d − 1) — the pooled variance of a one-way layout (each domain's spread from a few
    baseline runs is itself uncertain; its own z would favour a domain whose few runs
    happened to agree). Whether a
    domain's evidence passes is still judged against its own spread (:meth:`Evidence.
    passes_at`)."""
    def family(ev: Evidence) -> str:  # one statistic: a bearing line's share is its own
        return ev.measure if "band energy" in ev.measure else "coherent"

    acc: dict[str, list[float]] = {}
    for ev in evidence:
        if ev.n >= 2 and math.isfinite(ev.std) and math.isfinite(ev.mean) and ev.mean > 0:
            a = acc.setdefault(family(ev), [0.0, 0.0])
            a[0] += (ev.n - 1) * ev.std**2
            a[1] += ev.n - 1
    pooled = {f: math.sqrt(a[0] / a[1]) for f, a in acc.items() if a[1] > 0}

    def score(ev: Evidence) -> float:
        sp = pooled.get(family(ev))
        if sp is None or not (ev.n >= 2 and ev.mean > 0 and ev.value > 0) or sp <= 0:
            return float(ev.z)
        return math.log(ev.value / ev.mean) / (sp * math.sqrt(1.0 + 1.0 / ev.n))

    return score


def combined_score(scores: Sequence[float]) -> float:
    """Gaussian-equivalent score of the best of several evidence scores of one hypothesis
    (its common-domain cSDR and the planet-separated cSDR of each planet of a set), Šidák-
    adjusted for their number k: p = 1 − (1 − Φ(−z_max))^k, z = Φ⁻¹(1 − p) (Šidák 1967), so
    a hypothesis with more evidence domains is not favoured by their number."""
    from scipy.stats import norm

    zs = [float(z) for z in scores if math.isfinite(z)]
    if not zs:
        return math.nan
    if len(zs) == 1:
        return zs[0]
    k = len(zs)
    log_p = float(norm.logsf(max(zs)))
    if log_p < -30.0:  # 1 − (1 − p)^k = k·p to far below double precision
        log_adj = math.log(k) + log_p
    else:
        log_adj = math.log(-math.expm1(k * math.log1p(-math.exp(log_p))))
    if log_adj < -700.0:  # beyond exp's range: the asymptotic inverse of the normal tail
        return math.sqrt(-2.0 * log_adj - math.log(-4.0 * math.pi * log_adj))
    return float(norm.isf(math.exp(log_adj)))


def log_ratio_median(a: np.ndarray | None, b: np.ndarray | None) -> float:
    """Median over the orders of ``log(a/b)`` (both finite and > 0; NaN when none is):
    how much larger one planet's per-order deviation is than another's, robust to the few
    strong orders that dominate a power sum."""
    if a is None or b is None:
        return math.nan
    k = min(a.size, b.size)
    x, y = np.asarray(a[:k], float), np.asarray(b[:k], float)
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    return float(np.median(np.log(x[ok] / y[ok]))) if ok.any() else math.nan


def _pair_p(a: Evidence, b: Evidence) -> float:
    """One-sided p-value that planet ``a``'s deviation exceeds ``b``'s by more than the
    healthy members show (:func:`name_planet`)."""
    from scipy.stats import t as student

    from geardyn.diagnosis.baseline import prediction_spread

    value = log_ratio_median(a.deviation, b.deviation)
    null = [log_ratio_median(x, y) for x, y in zip(a.null_deviation, b.null_deviation,
                                                     strict=False)]
    keep = [i for i, v in enumerate(null) if math.isfinite(v)]
    if len(keep) < 2 or not math.isfinite(value):
        return math.nan
    runs = list(a.null_runs) if len(a.null_runs) == len(null) else None
    mu, scale, df = prediction_spread(np.asarray([null[i] for i in keep]),
                                      None if runs is None else [runs[i] for i in keep])
    if not (math.isfinite(scale) and scale > 0):
        return math.nan
    return float(student.sf((value - mu) / scale, df))


def name_planet(evidence: Mapping[str, Evidence], confidence: float
                ) -> tuple[str | None, float]:
    """The planet of a set whose synchronous deviation exceeds every other planet's, order
    by order, by more than the healthy baseline shows between the same planets. For planets
    a and b the statistic is the median over the orders of ``log(d_a(o)/d_b(o))``, d the
    per-order deviation power of the planet-separated rows against the baselines
    (``Evidence.deviation``; McFadden 1991 windows): a crack on a planet raises its own rows'
    deviation at most orders of its broadband signature, a healthy planet's rows differ from
    another's only by noise and by a fixed window-to-window offset, which the baseline
    members measure (the same statistic of each member against the others, leaving its run
    out: ``Evidence.null_deviation``). The record's statistic against that null sample gives
    a one-sided Student prediction p-value (runs as random effects:
    :func:`geardyn.diagnosis.baseline.prediction_spread`; Hahn & Meeker 1991, ch. 4). A
    planet is named when each of its N − 1 p-values is ≤ (1 − confidence)/N (a union bound
    over the N planets that could be named). Returns the planet (None when the evidence does
    not separate the planets) and the largest p-value of the best-separated planet."""
    usable = {p: e for p, e in evidence.items()
              if e.deviation is not None and len(e.null_deviation) >= 2}
    if len(usable) < 2 or len(usable) < len(evidence):
        return None, math.nan
    worst = {p: max((_pair_p(e, o) for q, o in usable.items() if q != p),
                    key=lambda v: v if math.isfinite(v) else math.inf)
             for p, e in usable.items()}
    finite = {p: v for p, v in worst.items() if math.isfinite(v)}
    if not finite:
        return None, math.nan
    best = min(finite, key=finite.get)
    p_value = finite[best]
    return (best if p_value <= (1.0 - confidence) / len(usable) else None), p_value


def _one_planet_set(names: list[str], info: Mapping[str, Any], kind: Mapping[str, str]) -> bool:
    """All ``names`` are planets of one planetary stage."""
    stages = {getattr(info.get(n), "stage", None) for n in names}
    return all(kind.get(n) == "planet" for n in names) and len(stages) == 1 \
        and None not in stages


def expected_match(location: list[str], expected: list[str], carriers: set[str],
                   kinds: Mapping[str, str], stages: Mapping[str, Any]) -> dict[str, Any]:
    """``missed`` (expected components not covered by the location), ``unexpected``
    (location components that are not expected: a shaft carrying a faulty member, and the
    other planets of a planet set that holds an expected planet, are accepted) and
    ``planet_named`` (an expected planet named alone)."""
    exp_stages = {stages.get(c) for c in expected if kinds.get(c) == "planet"}
    missed = [c for c in expected if c not in location]
    unexpected = [c for c in location if c not in expected
                  and not (c in carriers and kinds.get(c) == "shaft")
                  and not (kinds.get(c) == "planet" and stages.get(c) in exp_stages)]
    planet_set = [c for c in location if kinds.get(c) == "planet"]
    missed = [c for c in missed if not (kinds.get(c) == "planet" and planet_set
                                        and stages.get(c) in {stages.get(p) for p in planet_set})]
    named = bool(planet_set) and len(planet_set) == 1 and planet_set[0] in expected
    return {"missed": missed, "unexpected": unexpected,
            "planet_named": named if any(kinds.get(c) == "planet" for c in expected) else None}


__all__ = ["combined_score", "expected_match", "localise", "name_planet", "per_test_level",
           "pooled_scores", "posterior", "sidak_alpha"]
