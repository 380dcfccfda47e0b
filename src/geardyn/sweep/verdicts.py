"""Detection verdicts of every case of a sweep against the sweep's own healthy cases.

For each ``ok`` case, the baseline is every other ``ok`` case selected by
``[outputs.verdicts].healthy`` (axis values, e.g. ``{fault_gear = "none"}``) that shares the
case's values of the ``match`` axes (its operating point). Thresholds and detection are those
of ``geardyn diagnose`` (:func:`geardyn.diagnosis.baseline.thresholds`, μ + k·σ over the pooled
baseline blocks with the small-sample factor and σ floor; :func:`geardyn.diagnosis.verdict.
judge`, docs/diagnosis.md); a healthy case is left out of its own baseline, so its verdict
is a fair false-alarm test. Isolation (SDR, line concentrations) needs the per-revolution
blocks of the raw signals and is not repeated here: ``verdict`` is the detection state.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
import xarray as xr

if TYPE_CHECKING:
    from geardyn.sweep.spec import VerdictOutput


def _table(ind: np.ndarray, comps: list[str], kinds: list[str], inds: list[str],
           channel: str) -> pd.DataFrame:
    """Long indicator table (features COLUMNS) of one case from its (component, indicator,
    block) array; NaN entries left out."""
    c, i, b = np.nonzero(np.isfinite(ind))
    return pd.DataFrame({"component": np.asarray(comps, object)[c],
                         "kind": np.asarray(kinds, object)[c],
                         "indicator": np.asarray(inds, object)[i], "value": ind[c, i, b],
                         "block": b, "channel": channel})


def verdicts(ds: xr.Dataset, opts: VerdictOutput) -> xr.Dataset:
    """``verdict`` (alarm / healthy / unknown; '' when not judged) and ``margin`` (worst
    indicator's value/threshold) per (case, component) of the sweep data set ``ds``."""
    from geardyn.diagnosis.baseline import ThresholdRule, thresholds
    from geardyn.diagnosis.verdict import judge

    n = ds.sizes["case"]
    comps = [str(x) for x in ds["component"].values]
    kinds = [str(x) for x in ds["component_kind"].values]
    inds = [str(x) for x in ds["indicator"].values]
    channel = str(ds["indicators"].attrs.get("channel", ""))
    ind = np.asarray(ds["indicators"].values, float)
    status = np.asarray(ds["status"].values, dtype=object)
    ok = status == "ok"
    healthy = ok.copy()
    for k, v in opts.healthy.items():
        healthy &= np.asarray(ds[k].values == v)
    keys = [tuple(str(ds[a].values[i]) for a in opts.match) for i in range(n)]
    rule = ThresholdRule(k=opts.threshold_k or 3.0,
                         sigma_floor=0.05 if opts.sigma_floor is None else opts.sigma_floor)
    state = np.full((n, len(comps)), "", dtype=object)
    margin = np.full((n, len(comps)), np.nan)
    tables = {i: _table(ind[i], comps, kinds, inds, channel) for i in np.flatnonzero(ok)}
    cache: dict[tuple, pd.DataFrame] = {}
    for i in np.flatnonzero(ok):
        base = [j for j in np.flatnonzero(healthy) if j != i and keys[j] == keys[i]]
        if not base:
            continue
        ck = (keys[i], tuple(base))
        if ck not in cache:
            cache[ck] = thresholds([tables[j] for j in base], rule)
        v = judge(tables[i], cache[ck], rule, components=list(zip(comps, kinds, strict=True)))
        for c, cv in v.components.items():
            if c not in comps:
                continue
            k = comps.index(c)
            state[i, k] = cv.state
            w = cv.worst
            margin[i, k] = w[1] if w else np.nan
    return xr.Dataset({
        "verdict": (("case", "component"), state,
                    {"long_name": "detection state against the sweep's healthy cases at the "
                                  "same operating point ('' not judged)"}),
        "margin": (("case", "component"), margin,
                   {"units": "1", "long_name": "worst indicator's margin (value / threshold; "
                                               "> 1 alarm)"}),
    }, attrs={"verdict_rule": rule.describe(), "verdict_healthy": str(dict(opts.healthy)),
              "verdict_match": ",".join(opts.match)})


def write_verdicts(path: str | Path, opts: VerdictOutput) -> None:
    """Compute :func:`verdicts` from the store at ``path`` and write them into it."""
    from geardyn.sweep.store import _to_zarr, open_dataset

    ds = open_dataset(path)
    if "indicators" not in ds:
        return
    v = verdicts(ds, opts)
    v.attrs = {**ds.attrs, **v.attrs}
    _to_zarr(v.drop_vars([c for c in v.coords]), Path(path), mode="a")
