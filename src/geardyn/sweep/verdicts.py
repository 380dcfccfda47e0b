"""Verdicts of every case of a sweep against the sweep's own healthy cases: detection and
localisation, for the components the record is long enough to judge.

For each ``ok`` case, the baseline is every other ``ok`` case selected by
``[outputs.verdicts].healthy`` (axis values, e.g. ``{fault_gear = "none"}``) that shares the
case's values of the ``match`` axes (its operating point); a healthy case is left out of its
own baseline, so its verdict is a fair false-alarm test.

* **What can be judged.** A rotating component whose analysed record holds fewer than
  :data:`MIN_OWN_REVOLUTIONS` whole own revolutions (stored ``revolutions``, counted by the
  worker from the result) is not judged: a TSA block of fewer revolutions rejects too little
  non-synchronous content for its statistics to mean anything (the block rule of
  :mod:`geardyn.diagnosis.features`). Its state is ``not judged`` and ``verdict_note`` says
  why; a case with no judgeable component (or no healthy case at its operating point, or a
  run not ``ok``) is ``not judged``, and one with nothing detected among the components
  judged while others were too short is ``partly judged`` — never ``healthy``.
  ``geardyn sweep --check`` names such cases beforehand (:func:`short_case_notes`).
* **Level.** As :func:`geardyn.diagnosis.pipeline.judge_features`: each case has m tests
  (every usable detection threshold it has a value for, each isolation domain with
  statistics in the case and its baseline, each bearing line with a band energy); the
  per-test level is α = 1 − (1 − P)^(1/m) from ``false_alarm_probability`` P (Šidák 1967,
  :func:`level`) and k = Φ⁻¹(1 − α); an explicit ``threshold_k`` overrides k (α = Φ(−k)).
* **Detection.** Thresholds μ + k·σ over the baseline cases with the small-sample factor and
  σ floor (:func:`geardyn.diagnosis.baseline.thresholds`), judged per component
  (:func:`geardyn.diagnosis.verdict.judge`).
* **Localisation** (:func:`geardyn.diagnosis.localise.localise`, docs/diagnosis.md) from the
  isolation evidence of ``geardyn diagnose``, computed from what each case stores: the
  coherent synchronous deviation ratio of every own-angle, transmission-error and
  planet-separated domain (the per-order statistics ``isolation.*`` of the case against those
  of its baseline cases, leave-one-out null, :func:`geardyn.diagnosis.isolation.
  coherent_sdr`) and the bearings' fault-band energy shares (``band_energy`` against the
  baseline cases' shares, :func:`geardyn.diagnosis.isolation.evidence_from_null`), each test
  at α; the location needs the posterior ``localisation_confidence``. A detection without
  evidence ends ``uncertain`` with its candidates ranked by detection margin — never
  ``healthy``.

Stored per case (:data:`VARIABLES`): ``verdict_state`` (healthy / alarm = detected and
localised / uncertain / partly judged / not judged; '' pending), ``location`` (components,
comma-separated), ``location_confidence`` [1] (posterior of the location),
``localisation_state`` (none / localised / uncertain), ``localisation_level`` (component /
planet set / planet), ``candidates``, ``tests`` [1] (m), ``alpha_per_test`` [1],
``threshold_k`` [1], ``false_alarm_probability`` [1] (stated, or implied by threshold_k),
``verdict_note``; per component ``verdict`` and ``margin`` [1].
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr

from geardyn.diagnosis.features import MIN_REVS_PER_BLOCK
from geardyn.errors import InputError

if TYPE_CHECKING:
    from geardyn.sweep.spec import Sweep, VerdictOutput

#: Fewest whole own revolutions of a rotating component for its verdict: one TSA block of the
#: features' minimum (:data:`geardyn.diagnosis.features.MIN_REVS_PER_BLOCK`).
MIN_OWN_REVOLUTIONS = MIN_REVS_PER_BLOCK
#: Stored state of a component (or case) the record cannot support, and of a case with no
#: detection among the components judged while others were too short.
NOT_JUDGED = "not judged"
PARTLY_JUDGED = "partly judged"
#: Fewest planet-separated rows of a planet for its evidence (``#planet``, the evidence that
#: names a planet): per-order statistics need a variance between rows
#: (:func:`geardyn.diagnosis.isolation.order_stats`), and
#: :func:`geardyn.diagnosis.isolation.isolation_blocks` keeps planets with at least 2.
MIN_PLANET_ROWS = 2


def planet_row_revolutions(cfg: Any, channel: str | None, reference: str | None  # noqa: ANN401
                           ) -> float:
    """Reference revolutions an analysed record needs for :data:`MIN_PLANET_ROWS`
    planet-separated rows of every planet seen by the ring accelerometer ``channel``
    (0 when the channel is not on the fixed ring of a planetary stage).

    A row holds M = :func:`geardyn.diagnosis.planets.passes_per_row` consecutive planet
    passes (one per carrier revolution relative to the ring), rows start at multiples of M
    counted from the reference angle's origin, and a pass counts when its window of W
    ring-mesh periods (the default of :func:`geardyn.diagnosis.planets.planet_domains`,
    ``max(2, Z_r // 2N)``) lies inside the record. Whatever the record's phase, P
    consecutive passes hold ``floor((P + 1)/M) − 1`` whole rows at worst, so R rows need
    ``P = (R + 1)·M − 1`` passes, and P passes need ``P + (W + 1)/Z_r`` carrier revolutions
    (the window, plus one ring-mesh period for the rounding of the window's samples);
    divided by the carrier's revolutions relative to the ring per reference revolution."""
    from geardyn.diagnosis.components import machine_components
    from geardyn.diagnosis.planets import passes_per_row

    sensor = next((s for s in getattr(cfg, "sensors", []) if s.name == channel), None)
    if (sensor is None or sensor.kind != "accelerometer"
            or getattr(sensor, "location", None) != "ring"):
        return 0.0
    comps = machine_components(cfg, reference)
    stages = [st for st in comps.planetary if st.ring_fixed]
    st = next((x for x in stages if x.name == sensor.stage), None) if sensor.stage else (
        stages[0] if stages else None)
    if st is None or st.ring_ratio == 0.0:
        return 0.0
    zr, zp, n = st.ring_teeth, st.planet_ring_teeth, st.n_planets
    w = max(2, zr // (2 * n))
    m = passes_per_row(zr, zp, w)
    passes = (MIN_PLANET_ROWS + 1) * m - 1
    return (passes + (w + 1) / zr) / abs(st.ring_ratio)


def diagnosis_run_length_s(cfg: Any) -> float | None:  # noqa: ANN401
    """Planetary run length [s] whose analysed record (after ``diagnosis.skip_s``) holds, at
    the slowest speed of the baseline ensemble (input speed × (1 − ``ensemble.
    speed_tolerance``)), :data:`MIN_OWN_REVOLUTIONS` whole own revolutions of every rotating
    component and :data:`MIN_PLANET_ROWS` planet-separated rows of every planet
    (:func:`planet_row_revolutions`); None when the config states no input speed of its
    reference. The verdict's own requirements, nothing fitted."""
    from geardyn.diagnosis.isolation import ROTATING
    from geardyn.diagnosis.pipeline import options
    from geardyn.sweep.layout import _components, _reference

    if getattr(cfg, "planetary_dynamics", None) is None:
        return None
    o = options(cfg)
    ch = o.channel or next((s.name for s in getattr(cfg, "sensors", [])
                            if s.kind != "tacho"), None)
    ref = _reference(cfg, ch, o.reference)
    rpm = (getattr(cfg, "input_speeds_rpm", {}) or {}).get(ref)
    if rpm is None or rpm == 0:
        return None
    ratios = [r for _n, k, r in _components(cfg, ref) if k in ROTATING and r > 0]
    revs = max([MIN_OWN_REVOLUTIONS / min(ratios)] if ratios else [0.0])
    revs = max(revs, planet_row_revolutions(cfg, ch, ref))
    slowest = abs(float(rpm)) * (1.0 - o.ensemble.speed_tolerance) / 60.0
    return float(o.skip_s + revs / slowest)


def _table(ind: np.ndarray, comps: list[str], kinds: list[str], inds: list[str],
           channel: str, keep: np.ndarray) -> pd.DataFrame:
    """Long indicator table (features COLUMNS) of one case from its (component, indicator,
    block) array; NaN entries and components not ``keep`` left out."""
    ok = np.isfinite(ind) & keep[:, None, None]
    c, i, b = np.nonzero(ok)
    return pd.DataFrame({"component": np.asarray(comps, object)[c],
                         "kind": np.asarray(kinds, object)[c],
                         "indicator": np.asarray(inds, object)[i], "value": ind[c, i, b],
                         "block": b, "channel": channel})


class _Comps:
    """The minimal ``components`` object :func:`localise` reads (``items`` with ``name``,
    ``kind``, ``stage``, ``abs_ratio``)."""

    def __init__(self, items: list[Any]) -> None:
        self.items = items


def _components(sweep: Sweep | None, ds: xr.Dataset) -> _Comps | None:
    """Components of the base config (for the planet-set and shaft rules of localise)."""
    if sweep is None:
        return None
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis.components import machine_components
    from geardyn.errors import GeardynError
    from geardyn.sweep.layout import _reference

    try:
        cfg = parse_config(sweep.base)
        ind = sweep.spec.outputs.indicators
        return _Comps(list(machine_components(cfg, _reference(cfg, ind.channel, None)).items))
    except (GeardynError, KeyError, ValueError):
        return None


class _Isolation:
    """Coherent-SDR evidence from the stored per-order statistics (loaded per case on
    demand; the null sample of a baseline set is computed once)."""

    def __init__(self, ds: xr.Dataset) -> None:
        self.ds = ds
        self.labels = [str(x) for x in ds["domain"].values]
        self._stats: dict[int, list[Any]] = {}
        self._null: dict[tuple, list[float]] = {}

    def stats(self, i: int) -> list[Any]:
        """(OrderStats or None, ambiguous-order mask or None) of every domain of case ``i``."""
        from geardyn.diagnosis.isolation import OrderStats

        if i not in self._stats:
            row = self.ds.isel(case=i)
            re_ = np.asarray(row["isolation.mean_real"].values, float)
            im_ = np.asarray(row["isolation.mean_imag"].values, float)
            var = np.asarray(row["isolation.variance"].values, float)
            amb = (np.asarray(row["isolation.ambiguous"].values, float)
                   if "isolation.ambiguous" in row else np.full(re_.shape, np.nan))
            n = np.asarray(row["isolation.revolutions"].values, float)
            out: list[Any] = []
            for d in range(len(self.labels)):
                k = int(np.count_nonzero(np.isfinite(re_[d])))
                m = int(np.count_nonzero(np.isfinite(amb[d])))
                st = (OrderStats(re_[d, :k] + 1j * im_[d, :k], var[d, :k], int(n[d]))
                      if np.isfinite(n[d]) and n[d] >= 2 and k > 1 else None)
                out.append((st, amb[d, :m] > 0.5 if m else None))
            self._stats[i] = out
        return self._stats[i]

    def domains(self, i: int, base: list[int], skip: set[str]) -> list[tuple]:
        """The isolation domains case ``i`` has a test on against the baseline cases
        ``base``: (index, label, record stats, baseline stats, ambiguous-order mask) of every
        domain whose statistics the case and every baseline case hold, with a member not in
        ``skip`` (too short); own-angle domains first, then TE and planet-separated ones."""
        if len(base) < 2:
            return []
        rec = self.stats(i)
        bases = [self.stats(j) for j in base]
        out = []
        order = sorted(range(len(self.labels)),
                       key=lambda d: self.labels[d].startswith(("TE:", "planet:")))
        for d in order:
            label = self.labels[d]
            r, mask = rec[d]
            b = [s[d][0] for s in bases]
            if r is None or any(x is None for x in b) or not set(_members(label)) - skip:
                continue
            out.append((d, label, r, b, mask))
        return out

    def evidence(self, i: int, base: list[int], alpha: float, skip: set[str]
                 ) -> dict[str, Any]:
        """cSDR (own angle), cSDR_TE (a wheel's mesh; replaces its own-angle evidence) and
        cSDR_planet evidence (with the per-order deviations that name a planet) of case ``i``
        against the baseline cases ``base``, as :func:`geardyn.diagnosis.isolation.
        sdr_evidence` on the stored statistics: the record's ambiguous orders left out of
        every record; components in ``skip`` (too short) get none. (Planet-separated
        statistics come from every row of each case, not from the rows every case has:
        equal for cases of one run length.)"""
        from dataclasses import replace

        from geardyn.diagnosis.isolation import (
            _without,
            coherent_sdr,
            deviation_power,
            evidence_from_null,
            planet_deviation,
        )

        out: dict[str, Any] = {}
        for d, label, r, b, mask in self.domains(i, base, skip):
            if mask is not None:
                r, b = _without(r, mask), [_without(x, mask) for x in b]
            key = (d, tuple(base), b"" if mask is None else np.packbits(mask).tobytes())
            if key not in self._null:
                self._null[key] = [coherent_sdr(x, [y for k, y in enumerate(b) if k != m])
                                   for m, x in enumerate(b)]
            measure = ("cSDR_TE" if label.startswith("TE:") else "cSDR_planet"
                       if label.startswith("planet:") else "cSDR")
            ev = evidence_from_null("", measure, coherent_sdr(r, b), self._null[key],
                                    alpha, group=label)
            if measure == "cSDR_planet":
                p = _members(label)[0]
                if p not in skip:
                    power, dof = deviation_power(r, b)
                    out[f"{p}#planet"] = replace(  # each baseline case is its own run
                        ev, component=p, power=power, dof=dof,
                        **planet_deviation(r, b, list(range(len(b)))))
                continue
            for c in _members(label):
                if c not in skip:
                    out[c] = replace(ev, component=c)
        return out


def _members(label: str) -> list[str]:
    """Components of an isolation domain label (``sun``, ``a+b+c``, ``TE:<wheel>``,
    ``planet:<name>``)."""
    if label.startswith(("TE:", "planet:")):
        return [label.split(":", 1)[1]]
    return label.split("+")


def _detection_tests(th0: pd.DataFrame, table: pd.DataFrame) -> int:
    """Detection tests of a record (as judge_features counts them): every usable
    (component, kind, indicator, channel) threshold the record has a finite value for."""
    from geardyn.diagnosis.baseline import KEYS
    from geardyn.diagnosis.verdict import record_values

    if table.empty:
        return 0
    have = set(map(tuple, record_values(table)[KEYS].to_numpy().tolist()))
    return sum(1 for r in th0.loc[th0["usable"], KEYS].to_numpy().tolist()
               if tuple(r) in have)


#: Per-case verdict variables and their attributes.
_CASE_VARS: dict[str, dict[str, str]] = {
    "verdict_state": {"long_name": "machine verdict: healthy (nothing detected, every "
                      "component judged) / alarm (detected and localised) / uncertain "
                      "(detected, location uncertain) / partly judged (nothing detected "
                      "among the components judged; some too short to judge) / not judged "
                      "(nothing judgeable, no baseline, or the run not ok); '' pending"},
    "location": {"long_name": "components the fault is localised to (comma-separated; '' "
                 "none)"},
    "location_confidence": {"units": "1", "long_name": "posterior probability of the "
                            "location (uniform prior, Gaussian likelihood ratio of the "
                            "isolation evidence)"},
    "localisation_state": {"long_name": "localisation: none (nothing detected) / localised / "
                           "uncertain (candidates listed); '' not judged"},
    "localisation_level": {"long_name": "what the location names: component / planet set / "
                           "planet ('' not localised)"},
    "candidates": {"long_name": "candidate components of a detection whose location is "
                   "uncertain, most probable first (comma-separated)"},
    "tests": {"units": "1", "long_name": "tests m of the case: usable detection thresholds "
              "it has a value for + isolation statistics (many-tests correction)"},
    "alpha_per_test": {"units": "1", "long_name": "per-test false-alarm level α (Šidák 1967: "
                       "1 − (1 − P)^(1/m); Φ(−k) with threshold_k)"},
    "threshold_k": {"units": "1", "long_name": "threshold factor k = Φ⁻¹(1 − α) of the "
                    "detection thresholds mean + k·σ"},
    "false_alarm_probability": {"units": "1", "long_name": "machine-level false-alarm "
                                "probability P of the case's m tests (stated, or implied by "
                                "threshold_k)"},
    "verdict_note": {"long_name": "why components or the case were not judged"},
}


#: Every variable the verdicts write (axis names must differ from them).
VARIABLES = ("verdict", "margin", *_CASE_VARS)


def verdicts(ds: xr.Dataset, opts: VerdictOutput, sweep: Sweep | None = None) -> xr.Dataset:
    """Verdict variables (module docstring) of the sweep data set ``ds``."""
    from geardyn.diagnosis.baseline import ThresholdRule, thresholds
    from geardyn.diagnosis.isolation import ROTATING, evidence_from_null
    from geardyn.diagnosis.localise import localise, per_test_level
    from geardyn.diagnosis.verdict import judge

    n = ds.sizes["case"]
    comps = [str(x) for x in ds["component"].values]
    kinds = [str(x) for x in ds["component_kind"].values]
    inds = [str(x) for x in ds["indicator"].values]
    channel = str(ds["indicators"].attrs.get("channel", ""))
    ind = np.asarray(ds["indicators"].values, float)
    revs = (np.asarray(ds["revolutions"].values, float) if "revolutions" in ds
            else np.full((n, len(comps)), np.inf))
    band = np.asarray(ds["band_energy"].values, float) if "band_energy" in ds else None
    lines = [str(x) for x in ds["bearing_line"].values] if "bearing_line" in ds else []
    status = np.asarray(ds["status"].values, dtype=object)
    ok = status == "ok"
    healthy = ok.copy()
    for k, v in opts.healthy.items():
        healthy &= np.asarray(ds[k].values == v)
    keys = [tuple(str(ds[a].values[i]) for a in opts.match) for i in range(n)]
    floor = 0.05 if opts.sigma_floor is None else opts.sigma_floor
    rotating = np.array([k in ROTATING for k in kinds])
    short_all = rotating[None, :] & ~(revs >= MIN_OWN_REVOLUTIONS)
    bearings = np.flatnonzero(np.array(kinds) == "bearing")
    info = _components(sweep, ds)
    iso = _Isolation(ds) if "isolation.mean_real" in ds else None

    state = np.full((n, len(comps)), "", dtype=object)
    margin = np.full((n, len(comps)), np.nan)
    text = {v: np.full(n, "", dtype=object) for v in
            ("verdict_state", "location", "localisation_state", "localisation_level",
             "candidates", "verdict_note")}
    num = {v: np.full(n, np.nan) for v in
           ("location_confidence", "tests", "alpha_per_test", "threshold_k",
            "false_alarm_probability")}
    cache: dict[tuple, pd.DataFrame | None] = {}

    def table(j: int, keep: np.ndarray) -> pd.DataFrame:
        return _table(ind[j], comps, kinds, inds, channel, keep & ~short_all[j])

    def thresholds_of(base: list[int], keep: np.ndarray, k: float) -> pd.DataFrame | None:
        ck = (tuple(base), tuple(keep), k)
        if ck not in cache:
            tables = [table(j, keep) for j in base]
            try:  # (thresholds of only empty tables: ValueError of pandas, not InputError)
                cache[ck] = (thresholds(tables, ThresholdRule(k=k, sigma_floor=floor))
                             if any(not t.empty for t in tables) else None)
            except InputError:  # nothing judgeable in the baseline
                cache[ck] = None
        return cache[ck]

    for i in range(n):
        if status[i] in ("", None):
            continue  # pending
        if not ok[i]:
            text["verdict_state"][i] = "not judged"
            text["verdict_note"][i] = f"run status '{status[i]}'"
            continue
        short = short_all[i]
        keep = ~short
        skip = {comps[c] for c in np.flatnonzero(short)}
        base = [j for j in np.flatnonzero(healthy) if j != i and keys[j] == keys[i]]
        why = []
        if short.any():
            why.append("too short for the statistics (fewer than "
                       f"{MIN_OWN_REVOLUTIONS} whole own revolutions): "
                       + ", ".join(f"{comps[c]} {revs[i, c]:.3g}"
                                   for c in np.flatnonzero(short)))
        state[i, short] = NOT_JUDGED
        th0 = thresholds_of(base, keep, 3.0) if base else None
        if th0 is None:
            text["verdict_state"][i] = NOT_JUDGED
            state[i, state[i] == ""] = NOT_JUDGED
            text["verdict_note"][i] = "; ".join(
                [*why, "no healthy case at this operating point" if not base
                 else "no component could be judged"])
            continue
        # m tests, as judge_features counts them: usable detection thresholds the case has a
        # value for, each isolation domain, each bearing line with a baseline null
        record = table(i, keep)
        bearing_tests = [(c, li) for c in bearings for li in range(len(lines))
                         if band is not None and np.isfinite(band[i, c, li])
                         and np.isfinite(band[base, c, li]).sum() >= 2]
        m = (_detection_tests(th0, record) + len(bearing_tests)
             + (len(iso.domains(i, base, skip)) if iso is not None else 0))
        alpha, k_factor, p_fa = per_test_level(opts.false_alarm_probability, opts.threshold_k,
                                               m)
        th = thresholds_of(base, keep, k_factor)
        rule = ThresholdRule(k=k_factor, sigma_floor=floor)
        v = judge(record, th, rule, components=list(zip(comps, kinds, strict=True)))
        evidence = {}
        for c, li in bearing_tests:
            ev = evidence_from_null(comps[c], f"{lines[li]} band energy", band[i, c, li],
                                    [band[j, c, li] for j in base], alpha, group=comps[c])
            best = evidence.get(comps[c])
            if math.isfinite(ev.threshold) and (best is None or ev.z > best.z):
                evidence[comps[c]] = ev
        if iso is not None:
            evidence.update(iso.evidence(i, base, alpha, skip))
        localise(v, evidence, info, alpha=alpha, false_alarm_probability=p_fa, tests=max(m, 1),
                 confidence=opts.localisation_confidence)
        judged = [c for n_, c in v.components.items() if n_ not in skip
                  and c.state != "unknown"]
        loc = v.localisation or {}
        machine = v.state
        if not judged:
            machine = NOT_JUDGED
            why.append("no component could be judged")
        elif machine == "healthy" and short.any():
            machine = PARTLY_JUDGED
        text["verdict_state"][i] = machine
        text["location"][i] = ",".join(v.location)
        text["localisation_state"][i] = str(loc.get("state") or "")
        text["localisation_level"][i] = str(loc.get("level") or "")
        if loc.get("state") == "uncertain":
            text["candidates"][i] = ",".join(dict.fromkeys(
                str(x["component"]) for x in loc.get("candidates", [])))
        conf = loc.get("confidence")
        num["location_confidence"][i] = float(conf) if conf is not None else np.nan
        num["tests"][i] = max(m, 1)
        num["alpha_per_test"][i] = alpha
        num["threshold_k"][i] = k_factor
        num["false_alarm_probability"][i] = p_fa
        for c, cv in v.components.items():
            if c in comps and c not in skip:
                k = comps.index(c)
                state[i, k] = cv.state
                w = cv.worst
                margin[i, k] = w[1] if w else np.nan
        text["verdict_note"][i] = "; ".join(why)
    out = {
        "verdict": (("case", "component"), state,
                    {"long_name": "component state after detection and localisation against "
                                  "the sweep's healthy cases at the same operating point "
                                  f"('{NOT_JUDGED}': too short or no baseline; '' pending)"}),
        "margin": (("case", "component"), margin,
                   {"units": "1", "long_name": "worst detection indicator's margin (value / "
                                               "threshold; > 1 alarm)"}),
    }
    for name, attrs in _CASE_VARS.items():
        out[name] = (("case",), text[name] if name in text else num[name], attrs)
    return xr.Dataset(out, attrs={
        "verdict_rule": ("detection thresholds as geardyn diagnose (geardyn.diagnosis."
                         f"baseline.ThresholdRule, σ floor {floor:g}·|mean|) with each case's "
                         "factor threshold_k; isolation evidence at its alpha_per_test"),
        "verdict_false_alarm_probability": (
            "threshold_k given" if opts.threshold_k is not None
            else float(opts.false_alarm_probability)),
        "verdict_threshold_k": ("from false_alarm_probability (Šidák 1967)"
                                if opts.threshold_k is None else float(opts.threshold_k)),
        "verdict_localisation_confidence": float(opts.localisation_confidence),
        "verdict_healthy": str(dict(opts.healthy)), "verdict_match": ",".join(opts.match),
        "verdict_min_own_revolutions": MIN_OWN_REVOLUTIONS})


def short_case_notes(sweep: Sweep, most: int = 5) -> list[str]:
    """``geardyn sweep --check``: the cases whose analysed record is too short to judge some
    rotating components (predicted from the nominal input speed by
    :func:`geardyn.sweep.layout.short_cases`), each named by its axis values with its short
    components' revolutions, the rule and the run length that would judge them; the first
    ``most`` distinct case configs, then a count."""
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis.isolation import ROTATING
    from geardyn.diagnosis.pipeline import options
    from geardyn.sweep.layout import _components as components
    from geardyn.sweep.layout import _reference, _t_end, _where, short_cases

    short = short_cases(sweep, MIN_OWN_REVOLUTIONS)
    if not short:
        return []
    ind = sweep.spec.outputs.indicators
    out = [f"{len(short)} distinct case config(s) are too short for the statistics: a rotating "
           f"component needs at least {MIN_OWN_REVOLUTIONS} whole own revolutions in the "
           "analysed record (run length − skip_s, at the nominal input speed: one TSA block "
           f"of geardyn.diagnosis.features.MIN_REVS_PER_BLOCK = {MIN_REVS_PER_BLOCK}); "
           f"those components are stored '{NOT_JUDGED}', and a case with nothing detected "
           f"among the others '{PARTLY_JUDGED}' (nothing judgeable: '{NOT_JUDGED}')"]
    for sc in short[:most]:
        cfg = parse_config(sweep.case_config(sweep.cases[sc.index]))
        t_end = _t_end(sweep, cfg)
        o = options(cfg, channel=ind.channel, skip_s=ind.skip_s)
        rotating = {n for n, k, r in components(cfg, _reference(cfg, o.channel, o.reference))
                    if k in ROTATING and r > 0}
        slowest = min(sc.components.values())
        need = (f"; {o.skip_s + (t_end - o.skip_s) * MIN_OWN_REVOLUTIONS / slowest:.3g} s "
                "would judge them all (run.t_end_s)" if t_end is not None and slowest > 0
                else "")
        none = (f" (no component judgeable: the case will be '{NOT_JUDGED}')"
                if rotating <= set(sc.components) else "")
        out.append(f"{_where(sweep, sc.index)}: "
                   + ", ".join(f"{c} {r:.2g}" for c, r in sc.components.items())
                   + f" revolutions{none}{need}")
    if len(short) > most:
        out.append(f"… and {len(short) - most} more distinct case config(s)")
    return out


def planet_row_notes(sweep: Sweep, most: int = 5) -> list[str]:
    """``geardyn sweep --check``: the planetary cases (with ``[outputs.diagnosis]`` or
    ``[outputs.verdicts]``) whose analysed record, at the case's nominal input speed, holds
    fewer carrier revolutions than :data:`MIN_PLANET_ROWS` planet-separated rows per planet
    need (:func:`planet_row_revolutions`): no planet can be named there (a planet fault is
    localised to the planet set at best); each with the run length that would name one."""
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis.pipeline import options
    from geardyn.sweep.layout import _distinct, _reference, _t_end, _where, _without_faults

    out_spec = sweep.spec.outputs
    if out_spec.diagnosis is None and out_spec.verdicts is None:
        return []
    notes = []
    seen: set[str] = set()
    for index, data in _distinct(sweep):
        machine = _without_faults(data)  # one note per machine and run: faults, record
        (machine.get("diagnosis") or {}).pop("record_seed", None)  # seeds change nothing
        key = json.dumps(machine, sort_keys=True, default=str)
        if key in seen:
            continue
        seen.add(key)
        cfg = parse_config(data)
        t_end = _t_end(sweep, cfg)
        if t_end is None:
            continue
        channel = (out_spec.indicators.channel if out_spec.diagnosis is None else None)
        o = options(cfg, channel=channel,
                    skip_s=out_spec.indicators.skip_s if out_spec.diagnosis is None else None)
        ch = o.channel or next((s.name for s in cfg.sensors if s.kind != "tacho"), None)
        ref = _reference(cfg, ch, o.reference)
        rpm = (getattr(cfg, "input_speeds_rpm", {}) or {}).get(ref)
        if rpm is None or rpm == 0:
            continue
        need = planet_row_revolutions(cfg, ch, ref)
        have = max(t_end - o.skip_s, 0.0) * abs(float(rpm)) / 60.0
        if need > have:
            notes.append(f"{_where(sweep, index)}: {have:.3g} reference revolutions after "
                         f"skip_s, {need:.3g} give every planet {MIN_PLANET_ROWS} "
                         f"planet-separated rows; {o.skip_s + need / have * (t_end - o.skip_s):.3g}"
                         " s would (run length)")
    if not notes:
        return []
    head = (f"{len(notes)} planetary machine(s) of the sweep run too short to name a planet: "
            f"the evidence that names one needs {MIN_PLANET_ROWS} planet-separated rows per "
            "planet (geardyn.diagnosis.planets; docs/sweeps.md), without it a planet fault is "
            "localised to the planet set at best")
    return [head, *notes[:most]] + ([f"… and {len(notes) - most} more"]
                                    if len(notes) > most else [])


def write_verdicts(path: str | Path, sweep: Sweep) -> None:
    """Compute :func:`verdicts` from the store at ``path`` and write them into it."""
    from geardyn.sweep.store import _to_zarr, open_dataset

    opts = sweep.spec.outputs.verdicts
    if opts is None:
        return
    ds = open_dataset(path)
    if "indicators" not in ds:
        return
    v = verdicts(ds, opts, sweep)
    v.attrs = {**ds.attrs, **v.attrs}
    _to_zarr(v.drop_vars([c for c in v.coords]), Path(path), mode="a")
