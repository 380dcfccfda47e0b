"""The Zarr store of a sweep: one xarray data set with a ``case`` dimension.

Layout (``geardyn.sweep/1``):

* coordinates along ``case``: one per axis (its labels: the values, or ``labels`` of the
  spec), ``replicate``, ``seed`` (the case's run seed, :func:`geardyn.sweep.spec.case_seed`);
* ``status`` (``''`` while pending; the run's status ``ok``/``diverged``/``suspect``/… or
  ``failed``) and ``message``; ``wall_time_s`` (time the worker spent on the case — the only
  variable that differs between two runs of one sweep);
* ``channels.<name>`` (case, ``<name>.sample``) with ``channels.<name>.time`` [s]
  (and ``.angle`` [rad] for encoder channels), NaN-padded;
* ``state.<var>`` (case, state_time, shaft | mesh);
* ``indicators`` (case, component, indicator, block), with ``component_kind``;
* ``verdict`` and ``margin`` (case, component) when the spec asks for verdicts.

Every per-case variable is chunked one case per chunk. The driver alone writes: a case's data
first, then its ``status`` (the commit mark: a case without status is pending and is run
again on resume, overwriting the same chunks). The store is created aside and renamed into
place, and zarr's local store writes each chunk file atomically (temporary file + rename), so
the store stays readable whenever the driver is killed.
"""

from __future__ import annotations

import json
import os
import shutil
import uuid
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from geardyn.errors import InputError

if TYPE_CHECKING:
    from geardyn.sweep.spec import Sweep

LAYOUT = "geardyn.sweep/1"
PENDING = ""


def _strings(values: list[str]) -> np.ndarray:
    return np.array(values, dtype=object)


def _to_zarr(ds: xr.Dataset, path: Path, **kw: Any) -> Any:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # zarr v3 notes on string dtypes / consolidation
        return ds.to_zarr(path, consolidated=False, **kw)


def _open(path: Path) -> xr.Dataset:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xr.open_zarr(path, consolidated=False)


def create(path: str | Path, sweep: Sweep) -> None:
    """A new store for ``sweep``: case coordinates, empty status, provenance attributes."""
    from geardyn import __version__

    p = Path(path)
    n = len(sweep.cases)
    coords: dict[str, Any] = {"case": ("case", np.arange(n, dtype=np.int64),
                                       {"long_name": "case index"})}
    for k, a in enumerate(sweep.axes):
        labels = [c.labels(sweep.axes)[a.name] for c in sweep.cases]
        arr = _strings(labels) if isinstance(labels[0], str) else np.asarray(labels)
        attrs = {"path": a.path, "units": a.units, "long_name": a.name, "group": a.group,
                 "axis_index": k}
        if any(not isinstance(v, bool | int | float | str) for v in a.values):
            attrs["values"] = json.dumps(dict(zip(map(str, a.labels), a.values, strict=True)))
        coords[a.name] = ("case", arr, attrs)
    coords["replicate"] = ("case", np.array([c.replicate for c in sweep.cases], np.int64),
                           {"long_name": "replicate of the combination"})
    coords["seed"] = ("case", np.array([c.seed for c in sweep.cases], np.int64),
                      {"long_name": "run seed: SeedSequence([sweep seed, case]) first word"})
    data = {
        "status": ("case", _strings([PENDING] * n),
                   {"long_name": "'' pending; ok / diverged / suspect / stopped / reversed "
                                 "(run status) or failed"}),
        "message": ("case", _strings([""] * n), {"long_name": "why a case is not ok"}),
        "wall_time_s": ("case", np.full(n, np.nan), {"units": "s",
                                                     "long_name": "worker time of the case"}),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs = {
        "geardyn_layout": LAYOUT,
        "geardyn_version": __version__,
        "name": sweep.spec.sweep.name,
        "spec": json.dumps(sweep.spec_dict, sort_keys=True, default=str),
        "spec_hash": sweep.spec_hash,
        "base_config": str(sweep.base_path),
        "base_config_sha256": sweep.base_hash,
        "base_config_json": json.dumps(sweep.base, sort_keys=True),
        "sweep_seed": sweep.spec.sweep.seed,
        "seed_rule": "seed = SeedSequence([sweep_seed, case]).generate_state(1)[0]",
        "combine": sweep.spec.sweep.combine,
        "axes": json.dumps([a.name for a in sweep.axes]),
    }
    enc = {v: {"chunks": (1,)} for v in data}
    # written aside and renamed: a store at ``path`` is always complete
    tmp = p.with_name(f".{p.name}.creating-{uuid.uuid4().hex[:8]}")
    try:
        _to_zarr(ds, tmp, mode="w-", encoding=enc)
        os.rename(tmp, p)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


def open_store(path: str | Path) -> xr.Dataset:
    """The store at ``path`` (lazy); InputError when it is not a sweep store."""
    p = Path(path)
    if not p.exists():
        raise InputError(f"sweep store '{p}' does not exist")
    try:
        ds = _open(p)
    except (OSError, ValueError, KeyError) as exc:
        raise InputError(f"'{p}' is not a readable Zarr store: {exc}") from None
    if ds.attrs.get("geardyn_layout") != LAYOUT:
        raise InputError(f"'{p}' is not a geardyn sweep store (layout "
                         f"{ds.attrs.get('geardyn_layout')!r}, expected {LAYOUT!r})")
    return ds


def open_dataset(path: str | Path) -> xr.Dataset:
    """A sweep data set (``geardyn sweep ... --out PATH``) as xarray, lazily loaded (dask);
    ``status``, ``message``, string coordinates and ``verdict`` as Python strings."""
    ds = open_store(path)
    for name in list(ds.variables):
        v = ds[name]
        if v.dtype.kind in ("T", "O", "U"):
            ds[name] = v.copy(data=np.asarray(v.values, dtype=object))
    return ds


def statuses(path: str | Path) -> np.ndarray:
    """Status of every case (``''`` pending)."""
    return np.asarray(_open(Path(path))["status"].values, dtype=object)


def _case_dims(name: str, entry: tuple) -> tuple[str, ...]:
    return ("case", *entry[2])


def ensure_variables(path: str | Path, arrays: dict[str, tuple], kinds: dict[str, str],
                     n_cases: int) -> None:
    """Add to the store, full size and NaN-filled (metadata only), the per-case variables of a
    case result not yet in it, with the coordinates of their new dimensions."""
    import dask.array as da

    p = Path(path)
    store = _open(p)
    new = {k: e for k, e in arrays.items() if k not in store.data_vars}
    if not new:
        return
    coords: dict[str, Any] = {}
    sizes: dict[str, int] = {}
    for _name, (values, _attrs, dims, cds) in new.items():
        for d, n in zip(dims, np.shape(values), strict=True):
            if d in store.dims:
                sizes[d] = store.sizes[d]
                continue
            sizes[d] = max(sizes.get(d, 0), n)
            if d in cds and d not in coords:
                lab = list(cds[d])
                if d in ("component", "indicator", "shaft", "mesh"):
                    lab = sorted(str(x) for x in lab)
                    arr: Any = _strings(lab)
                else:
                    arr = np.asarray(lab)
                coords[d] = (d, arr)
                sizes[d] = len(lab)
    if "component" in coords:
        comps = list(coords["component"][1])
        coords["component_kind"] = ("component", _strings([kinds.get(c, "") for c in comps]))
    data = {}
    enc = {}
    for name, (_values, attrs, dims, _cds) in new.items():
        shape = (n_cases, *(sizes[d] for d in dims))
        data[name] = (("case", *dims), da.full(shape, np.nan, chunks=(1, *shape[1:])), attrs)
        enc[name] = {"chunks": (1, *shape[1:]), "fill_value": np.nan}
    ds = xr.Dataset(data, coords=coords, attrs=dict(store.attrs))
    if "state_time" in coords:
        ds["state_time"].attrs.update(units="s", long_name="time of the state samples")
    _to_zarr(ds, p, mode="a", compute=False, encoding=enc)


class Writer:
    """Writes cases into the store at ``path`` through zarr (one chunk per case and
    variable); the store's layout (dimension labels and sizes) is read once and again only
    after :meth:`ensure_variables` adds variables."""

    def __init__(self, path: str | Path, n_cases: int) -> None:
        self.path = Path(path)
        self.n_cases = n_cases
        self._refresh()

    def _refresh(self) -> None:
        import zarr

        ds = _open(self.path)
        self.names = set(ds.data_vars)
        self.sizes = dict(ds.sizes)
        self.labels = {d: {str(x): k for k, x in enumerate(ds[d].values)}
                       for d in ("component", "indicator", "shaft", "mesh") if d in ds.coords}
        self.group = zarr.open_group(str(self.path), mode="r+")

    def ensure_variables(self, arrays: dict[str, tuple], kinds: dict[str, str]) -> None:
        """Add the result's variables the store lacks (see :func:`ensure_variables`)."""
        if set(arrays) - self.names:
            ensure_variables(self.path, arrays, kinds, self.n_cases)
            self._refresh()

    def _aligned(self, values: np.ndarray, dims: list[str], cds: dict[str, Any]
                 ) -> tuple[np.ndarray, list[str]]:
        """``values`` on the store's grid of ``dims`` (labels matched, samples NaN-padded);
        labels the store lacks are dropped and returned."""
        out = np.full([self.sizes[d] for d in dims], np.nan)
        dropped: list[str] = []
        src: list[np.ndarray] = []
        dst: list[np.ndarray] = []
        for d, n in zip(dims, np.shape(values), strict=True):
            if d in cds and d in self.labels:
                have = self.labels[d]
                lab = [str(x) for x in cds[d]]
                keep = [k for k, x in enumerate(lab) if x in have]
                dropped += [f"{d} {x}" for x in lab if x not in have]
                src.append(np.array(keep, int))
                dst.append(np.array([have[lab[k]] for k in keep], int))
            else:
                m = min(n, self.sizes[d])
                src.append(np.arange(m))
                dst.append(np.arange(m))
        out[np.ix_(*dst)] = np.asarray(values, float)[np.ix_(*src)]
        return out, dropped

    def write_case(self, index: int, result: dict[str, Any]) -> None:
        """Write one case's arrays, then its message and wall time, then its status (the
        commit mark)."""
        dropped: list[str] = []
        for name, (values, _attrs, dims, cds) in result["arrays"].items():
            if name not in self.names:
                dropped.append(name)
                continue
            arr, d = self._aligned(values, list(dims), cds)
            dropped += d
            self.group[name][index] = arr
        message = str(result["message"])
        if dropped:
            message += ("; " if message else "") + "not stored (not in the store's layout): " \
                + ", ".join(sorted(set(dropped))[:10])
        self.group["message"][index] = message
        self.group["wall_time_s"][index] = float(result.get("wall_time_s", np.nan))
        self.group["status"][index] = str(result["status"])


def check_same_sweep(path: str | Path, sweep: Sweep) -> xr.Dataset:
    """The existing store at ``path`` if it was made by ``sweep`` (same spec and base config);
    InputError otherwise."""
    ds = open_store(path)
    if ds.attrs.get("spec_hash") != sweep.spec_hash or ds.sizes["case"] != len(sweep.cases):
        raise InputError(
            f"--out: '{path}' holds another sweep (spec hash {ds.attrs.get('spec_hash')}, "
            f"{ds.sizes['case']} cases; this spec: {sweep.spec_hash}, {len(sweep.cases)} cases):"
            " give a new --out, or delete the store to start again")
    return ds
