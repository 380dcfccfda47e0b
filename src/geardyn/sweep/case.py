"""One case of a sweep, as a dask worker runs it: simulate, measure, extract, pack.

:func:`run_case` takes a plain dict (the case's validated config as a dict, its seed, the run
overrides and the outputs to keep) and returns a plain dict of numpy arrays: no live object
crosses the network, and the driver alone writes the store. A case that raises records
``status = 'failed'`` and the error; it never fails the dask task.
"""

from __future__ import annotations

import math
import time
import traceback
from typing import Any

import numpy as np

#: Status of a case that raised (the run's own statuses: ok, diverged, suspect, stopped, …).
STATUS_FAILED = "failed"


def _decimated(values: np.ndarray, t: np.ndarray, every: int, sampling: str
               ) -> tuple[np.ndarray, np.ndarray]:
    """Every ``every``-th sample; a uniformly time-sampled channel is low-pass filtered first
    (zero-phase FIR of scipy.signal.decimate: 20·every + 1 taps, Hamming window, cut-off at
    the new Nyquist frequency)."""
    if every == 1:
        return values, t
    if sampling == "time" and values.size > 60 * every:
        from scipy.signal import decimate

        return decimate(values, every, ftype="fir", zero_phase=True), t[::every]
    return values[::every], t[::every]


def _channel(ds: Any, name: str, every: int, samples: int) -> dict[str, Any]:
    from geardyn.results import channel

    ch = channel(ds, name)
    vals, t = _decimated(np.asarray(ch.values, float), np.asarray(ch.time, float), every,
                         ch.sampling)
    dims = [f"{name}.sample"]
    kept = min(vals.size, samples)
    out = {f"channels.{name}.length": (np.array(float(kept)), {}, [], {}),
           f"channels.{name}.samples_computed": (np.array(float(vals.size)), {}, [], {}),
           f"channels.{name}": (vals[-samples:], {"units": ch.units, "long_name": name,
                                                   "sensor_kind": ch.kind,
                                                   "sampling": ch.sampling, "shaft": ch.shaft},
                                dims, {}),
           f"channels.{name}.time": (t[-samples:], {"units": "s",
                                                     "long_name": f"{name} sample time"},
                                     dims, {})}
    if ch.angle is not None:
        ang = ch.angle[::every]
        out[f"channels.{name}.angle"] = (ang[-samples:], {
            "units": "rad", "long_name": f"{name}: angle of shaft {ch.shaft}"}, dims, {})
    return out


def _states(ds: Any, names: list[str], step_s: float, n: int | None) -> dict[str, Any]:
    """States on the grid ``k·step_s`` (linear interpolation in time); NaN past the run end."""
    t = np.asarray(ds["time"].values, float)
    if n is None:
        n = int(math.floor(t[-1] / step_s + 1e-9)) + 1
    grid = np.arange(n) * step_s
    out: dict[str, Any] = {}
    for v in names:
        if v not in ds:
            continue
        da = ds[v]
        other = [d for d in da.dims if d != "time"]
        arr = np.asarray(da.transpose("time", *other).values, float)
        res = np.full((n, *arr.shape[1:]), np.nan)
        inside = grid <= t[-1] + 1e-12
        for j in np.ndindex(*arr.shape[1:]):
            res[(inside, *j)] = np.interp(grid[inside], t, arr[(slice(None), *j)])
        coords: dict[str, Any] = {d: [str(x) for x in ds[d].values] for d in other}
        coords["state_time"] = grid
        out[f"state.{v}"] = (res, {"units": str(da.attrs.get("units", "")),
                                   "long_name": str(da.attrs.get("long_name", v))},
                             ["state_time", *other], coords)
    return out


def _indicators(ds: Any, cfg: Any, opts: dict[str, Any]) -> dict[str, Any]:
    """Per-block indicator table of the channel (geardyn.diagnosis.features) as an array
    (component, indicator, block) and the component kinds."""
    from geardyn.diagnosis.features import features_from_result
    from geardyn.diagnosis.pipeline import options
    from geardyn.results import channel, channels

    o = options(cfg, channel=opts.get("channel"), skip_s=opts.get("skip_s"),
                blocks=opts.get("blocks"))
    ch = channel(ds, o.channel).name if o.channel else channels(ds)[0]
    feats = features_from_result(ds, cfg, ch, reference=o.reference, skip_s=o.skip_s,
                                 n_blocks=o.blocks)
    table = feats.table
    comps = list(dict.fromkeys(str(c) for c in table["component"]))
    inds = list(dict.fromkeys(str(c) for c in table["indicator"]))
    arr = np.full((len(comps), len(inds), o.blocks), np.nan)
    ci = {c: k for k, c in enumerate(comps)}
    ii = {c: k for k, c in enumerate(inds)}
    for c, i, b, v in zip(table["component"], table["indicator"], table["block"],
                          table["value"], strict=True):
        if int(b) < o.blocks:
            arr[ci[str(c)], ii[str(i)], int(b)] = float(v)
    kinds = dict(zip(table["component"].astype(str), table["kind"].astype(str), strict=False))
    return {**_judgeable(feats),
            "indicators": (arr, {"units": "1", "long_name": f"condition indicators of channel "
                                f"{ch} per block", "channel": ch},
                          ["component", "indicator", "block"],
                          {"component": comps, "indicator": inds,
                           "block": list(range(o.blocks))}),
            "_kinds": kinds}


def _judgeable(feats: Any) -> dict[str, Any]:
    """Whole own revolutions of every rotating component in the analysed record (0: left out
    for less than one; the TSA attribute ``revolutions``) and the fault-band energy share of
    every bearing line in the squared-envelope spectrum (:func:`geardyn.diagnosis.isolation.
    bearing_line_shares`, the bearings' isolation evidence), per component."""
    from geardyn.diagnosis.components import BEARING_LINES
    from geardyn.diagnosis.isolation import ROTATING, bearing_line_shares

    comps = feats.components
    if comps is None:
        return {}
    names = [c.name for c in comps.items]
    revs = np.full(len(names), np.nan)
    for k, c in enumerate(comps.items):
        if c.kind in ROTATING:
            t = feats.tsa.get(c.name)
            revs[k] = float(t.attrs.get("revolutions", 0)) if t is not None else 0.0
    out: dict[str, Any] = {"revolutions": (revs, {}, ["component"], {"component": names})}
    spec = (feats.bearing_spectrum if getattr(feats, "bearing_spectrum", None) is not None
            else feats.envelope_spectrum)
    lines = list(BEARING_LINES)
    if spec is not None and comps.bearings:
        o = np.asarray(spec["order"].values, float)
        s = np.asarray(spec.values, float)
        share = np.full((len(comps.bearings), len(lines)), np.nan)
        shares = bearing_line_shares(o, s, comps.bearings)
        for k, c in enumerate(comps.bearings):
            for line in c.fault_orders:
                if line in lines:
                    share[k, lines.index(line)] = shares[(c.name, line)]
        out["band_energy"] = (share, {}, ["component", "bearing_line"],
                              {"component": [c.name for c in comps.bearings],
                               "bearing_line": lines})
    return out


def _isolation(ds: Any, cfg: Any, opts: dict[str, Any]) -> dict[str, Any]:
    """Per-order synchronous statistics (:func:`geardyn.diagnosis.isolation.order_stats`: the
    mean revolution's spectrum and the revolutions' variance per order) of every own-angle,
    transmission-error and planet-separated domain of the channel, over the orders the domain
    compares (``top``), and its orders left out as ambiguous (another member's harmonic
    within the TSA's resolution, :func:`~geardyn.diagnosis.isolation.ambiguous_orders`; 1 =
    left out): all the coherent synchronous deviation ratio needs
    (:func:`~geardyn.diagnosis.isolation.coherent_sdr`), so that the sweep's verdicts weigh
    the same isolation evidence as ``geardyn diagnose``.
    A domain is labelled by its components (:func:`geardyn.sweep.layout.domain_labels`)."""
    from geardyn.diagnosis.isolation import isolation_blocks, order_stats
    from geardyn.diagnosis.pipeline import options
    from geardyn.results import channel, channels

    o = options(cfg, channel=opts.get("channel"), skip_s=opts.get("skip_s"),
                blocks=opts.get("blocks"))
    ch = channel(ds, o.channel).name if o.channel else channels(ds)[0]
    b = isolation_blocks(ds, cfg, ch, reference=o.reference, skip_s=o.skip_s)
    groups: dict[str, list[str]] = {}
    for c, key in b.of.items():
        groups.setdefault(key, []).append(c)
    labels = {key: "+".join(sorted(cs)) for key, cs in groups.items()}
    labels.update({key: f"TE:{w}" for w, key in b.of_te.items()})
    labels.update({key: f"planet:{p}" for p, key in b.of_planet.items()})
    names, stats, masks = [], [], []
    for key, rows in b.domains.items():
        if key in labels and rows.shape[0] >= 2:
            names.append(labels[key])
            stats.append(order_stats(rows, b.top.get(key)))
            masks.append(b.ambiguous.get(key))
    if not names:
        return {}
    k = max(st.mean.size for st in stats)
    re_, im_, var, amb = (np.full((len(names), k), np.nan) for _ in range(4))
    for j, st in enumerate(stats):
        re_[j, :st.mean.size] = st.mean.real
        im_[j, :st.mean.size] = st.mean.imag
        var[j, :st.var.size] = st.var
        if masks[j] is not None:
            amb[j, :masks[j].size] = masks[j]
    dims, cds = ["domain", "order"], {"domain": names}
    return {"isolation.mean_real": (re_, {}, dims, cds),
            "isolation.mean_imag": (im_, {}, dims, cds),
            "isolation.variance": (var, {}, dims, cds),
            "isolation.ambiguous": (amb, {}, dims, cds),
            "isolation.revolutions": (np.array([float(st.n) for st in stats]), {}, ["domain"],
                                      cds)}


def run_case(task: dict[str, Any]) -> dict[str, Any]:
    """Run one case (called on a dask worker). ``task``: ``index``, ``seed``, ``config``
    (validated config dict), ``run`` (run_simulation overrides), ``outputs`` (OutputSpec as a
    dict), ``state_samples`` (length of the state grid or None). Returns ``index``, ``status``,
    ``message``, ``wall_time_s`` and ``arrays``."""
    t0 = time.perf_counter()
    cpu0 = time.process_time()
    out: dict[str, Any] = {"index": task["index"], "status": STATUS_FAILED, "message": "",
                           "arrays": {}, "kinds": {}}
    try:
        from geardyn.config.loader import parse_config
        from geardyn.run import run_simulation

        cfg = parse_config(task["config"], source=f"case {task['index']}")
        run = {k: v for k, v in task["run"].items() if v is not None}
        outputs = task["outputs"]
        diag = outputs.get("diagnosis")
        rec = None
        run_seed = int(task["seed"])
        if diag is not None:  # the record of geardyn diagnose (geardyn.sweep.diagnosis)
            from geardyn.sweep.diagnosis import record

            rec = record(cfg, int(task["seed"]), task["run"], diag)
            cfg, run_seed = rec.config, rec.run_seed
            run = {k: v for k, v in rec.run_length.items() if v is not None}
        ds = run_simulation(cfg, seed=run_seed, **run)
        status = str(ds.attrs.get("status", "ok"))
        out["status"] = status
        out["message"] = str(ds.attrs.get("diagnosis", "")) if status != "ok" else ""
        if rec is not None and status == "ok":
            from geardyn.sweep.diagnosis import judge

            try:
                arrays, note = judge(ds, rec, int(task["seed"]), diag, task.get("store"), cpu0)
            except Exception as exc:  # noqa: BLE001 - recorded in the store, sweep goes on
                out["status"] = STATUS_FAILED
                out["message"] = f"diagnosis: {type(exc).__name__}: {exc}"
            else:
                out["arrays"].update(arrays)
                out["message"] = note
        ch = outputs["channels"]
        for name in ch["names"]:
            out["arrays"].update(_channel(ds, name, ch["every"], ch["samples"]))
        st = outputs["states"]
        out["arrays"].update(_states(ds, st["variables"], st["step_s"], task.get("state_samples")))
        if outputs["indicators"]["enabled"] and status == "ok":
            try:
                ind = _indicators(ds, cfg, outputs["indicators"])
            except Exception as exc:  # noqa: BLE001 - recorded in the store, sweep goes on
                out["status"] = STATUS_FAILED
                out["message"] = f"indicators: {type(exc).__name__}: {exc}"
            else:
                out["kinds"] = ind.pop("_kinds")
                out["arrays"].update(ind)
                if outputs.get("verdicts") is not None:
                    try:
                        out["arrays"].update(_isolation(ds, cfg, outputs["indicators"]))
                    except Exception as exc:  # noqa: BLE001 - recorded, the case stays
                        out["message"] = (f"isolation statistics not stored: "
                                          f"{type(exc).__name__}: {exc}")
    except Exception as exc:  # noqa: BLE001 - a failing case records its error
        out["status"] = STATUS_FAILED
        last = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
        where = f" (at {last.filename.rsplit('/', 1)[-1]}:{last.lineno})" if last else ""
        out["message"] = f"{type(exc).__name__}: {exc}{where}"
    out["wall_time_s"] = time.perf_counter() - t0
    return out
