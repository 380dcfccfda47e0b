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
  :mod:`geardyn.diagnosis.features`). Its state is ``unknown`` and ``verdict_note`` says why;
  a case with no judgeable component gets the machine state ``unknown``.
* **Detection.** Thresholds μ + k·σ over the pooled baseline blocks with the small-sample
  factor and σ floor (:func:`geardyn.diagnosis.baseline.thresholds`), k = ``threshold_k``
  (default 3), judged per component (:func:`geardyn.diagnosis.verdict.judge`).
* **Localisation** (:func:`geardyn.diagnosis.localise.localise`, docs/diagnosis.md) from the
  isolation evidence of ``geardyn diagnose``, computed from what each case stores: the
  coherent synchronous deviation ratio of every own-angle, transmission-error and
  planet-separated domain (the per-order statistics ``isolation.*`` of the case against those
  of its baseline cases, leave-one-out null, :func:`geardyn.diagnosis.isolation.
  coherent_sdr`) and the bearings' fault-band energy shares (``band_energy`` against the
  baseline cases' shares, :func:`geardyn.diagnosis.isolation.evidence_from_null`). Each test
  runs at α = Φ(−k); a detection without evidence ends ``uncertain`` with its candidates
  ranked by detection margin — never ``healthy``.

Stored: ``verdict_state`` (healthy / alarm = detected and localised / uncertain / unknown;
'' not judged), ``location`` (components, comma-separated), ``location_confidence`` [1]
(posterior of the location), ``verdict_note``; per component ``verdict`` and ``margin`` [1].
"""

from __future__ import annotations

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

    def evidence(self, i: int, base: list[int], alpha: float, skip: set[str]
                 ) -> dict[str, Any]:
        """cSDR (own angle), cSDR_TE (a wheel's mesh; replaces its own-angle evidence) and
        cSDR_planet evidence (with the deviation power that names a planet) of case ``i``
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
        )

        if len(base) < 2:
            return {}
        rec = self.stats(i)
        bases = [self.stats(j) for j in base]
        out: dict[str, Any] = {}
        order = sorted(range(len(self.labels)),
                       key=lambda d: self.labels[d].startswith(("TE:", "planet:")))
        for d in order:
            label = self.labels[d]
            r, mask = rec[d]
            b = [s[d][0] for s in bases]
            if r is None or any(x is None for x in b):
                continue
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
                p = label.split(":", 1)[1]
                if p not in skip:
                    power, dof = deviation_power(r, b)
                    out[f"{p}#planet"] = replace(ev, component=p, power=power, dof=dof)
                continue
            members = [label.split(":", 1)[1]] if measure == "cSDR_TE" else label.split("+")
            for c in members:
                if c not in skip:
                    out[c] = replace(ev, component=c)
        return out


def verdicts(ds: xr.Dataset, opts: VerdictOutput, sweep: Sweep | None = None) -> xr.Dataset:
    """Verdict variables (module docstring) of the sweep data set ``ds``."""
    from scipy.stats import norm

    from geardyn.diagnosis.baseline import ThresholdRule, thresholds
    from geardyn.diagnosis.isolation import ROTATING, evidence_from_null
    from geardyn.diagnosis.localise import localise
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
    k_factor = opts.threshold_k or 3.0
    rule = ThresholdRule(k=k_factor,
                         sigma_floor=0.05 if opts.sigma_floor is None else opts.sigma_floor)
    alpha = float(norm.sf(k_factor))
    rotating = np.array([k in ROTATING for k in kinds])
    info = _components(sweep, ds)
    iso = _Isolation(ds) if "isolation.mean_real" in ds else None

    state = np.full((n, len(comps)), "", dtype=object)
    margin = np.full((n, len(comps)), np.nan)
    machine = np.full(n, "", dtype=object)
    location = np.full(n, "", dtype=object)
    confidence = np.full(n, np.nan)
    notes = np.full(n, "", dtype=object)
    cache: dict[tuple, pd.DataFrame | None] = {}
    for i in np.flatnonzero(ok):
        short = rotating & ~(revs[i] >= MIN_OWN_REVOLUTIONS)
        keep = ~short
        base = [j for j in np.flatnonzero(healthy) if j != i and keys[j] == keys[i]]
        why = []
        if short.any():
            why.append("too short for the statistics (fewer than "
                       f"{MIN_OWN_REVOLUTIONS} whole own revolutions): "
                       + ", ".join(f"{comps[c]} {revs[i, c]:.3g}"
                                   for c in np.flatnonzero(short)))
        if not base:
            notes[i] = "; ".join([*why, "no healthy case at this operating point"])
            continue
        ck = (keys[i], tuple(base), tuple(keep))
        if ck not in cache:
            try:
                cache[ck] = thresholds([_table(ind[j], comps, kinds, inds, channel,
                                               keep & ~(rotating & ~(revs[j] >=
                                                                     MIN_OWN_REVOLUTIONS)))
                                        for j in base], rule)
            except InputError:  # nothing judgeable in the baseline
                cache[ck] = None
        if cache[ck] is None:
            machine[i] = "unknown"
            state[i] = "unknown"
            notes[i] = "; ".join([*why, "no component could be judged"])
            continue
        v = judge(_table(ind[i], comps, kinds, inds, channel, keep), cache[ck], rule,
                  components=list(zip(comps, kinds, strict=True)))
        evidence = {}
        if band is not None:
            for c in np.flatnonzero(np.array(kinds) == "bearing"):
                best = None
                for li, line in enumerate(lines):
                    ev = evidence_from_null(comps[c], f"{line} band energy", band[i, c, li],
                                            [band[j, c, li] for j in base], alpha,
                                            group=comps[c])
                    if math.isfinite(ev.threshold) and (best is None or ev.z > best.z):
                        best = ev
                if best is not None:
                    evidence[comps[c]] = best
        if iso is not None:
            evidence.update(iso.evidence(i, base, alpha, {comps[c] for c in
                                                          np.flatnonzero(short)}))
        tests = (sum(len(c.indicators) for c in v.components.values())
                 + len({ev.group for ev in evidence.values()}))
        localise(v, evidence, info, alpha=alpha,
                 false_alarm_probability=float(-math.expm1(max(tests, 1)
                                                           * math.log1p(-alpha))),
                 tests=max(tests, 1))
        judged = [c for c in v.components.values() if c.state != "unknown"]
        machine[i] = v.state if judged else "unknown"
        location[i] = ",".join(v.location)
        conf = (v.localisation or {}).get("confidence")
        confidence[i] = float(conf) if conf is not None else np.nan
        for c, cv in v.components.items():
            if c not in comps:
                continue
            k = comps.index(c)
            state[i, k] = cv.state
            w = cv.worst
            margin[i, k] = w[1] if w else np.nan
        if not judged:
            why.append("no component could be judged")
        notes[i] = "; ".join(why)
    return xr.Dataset({
        "verdict": (("case", "component"), state,
                    {"long_name": "component state after detection and localisation against "
                                  "the sweep's healthy cases at the same operating point "
                                  "('' not judged)"}),
        "margin": (("case", "component"), margin,
                   {"units": "1", "long_name": "worst detection indicator's margin (value / "
                                               "threshold; > 1 alarm)"}),
        "verdict_state": (("case",), machine,
                          {"long_name": "machine verdict: healthy / alarm (detected and "
                                        "localised) / uncertain (detected, location "
                                        "uncertain) / unknown (nothing judgeable); '' not "
                                        "judged"}),
        "location": (("case",), location,
                     {"long_name": "components the fault is localised to (comma-separated; "
                                   "'' none)"}),
        "location_confidence": (("case",), confidence,
                                {"units": "1", "long_name": "posterior probability of the "
                                 "location (uniform prior, Gaussian likelihood ratio of the "
                                 "isolation evidence)"}),
        "verdict_note": (("case",), notes,
                         {"long_name": "why components or the case were not judged"}),
    }, attrs={"verdict_rule": rule.describe(), "verdict_healthy": str(dict(opts.healthy)),
              "verdict_match": ",".join(opts.match),
              "verdict_min_own_revolutions": MIN_OWN_REVOLUTIONS})


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
