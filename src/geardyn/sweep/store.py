"""The Zarr store of a sweep: one xarray data set with a ``case`` dimension.

Layout (``geardyn.sweep/2``; every per-case variable and dimension is created with the store,
its shape fixed from the spec and the cases' own configs by :func:`geardyn.sweep.layout.plan`,
never by whichever case finishes first):

* coordinates along ``case``: one per axis (its labels: the values, or ``labels`` of the
  spec), ``replicate``, ``seed`` (the case's run seed, :func:`geardyn.sweep.spec.case_seed`);
* ``status`` (``''`` while pending; the run's status ``ok``/``diverged``/``suspect``/… or
  ``failed``) and ``message``; ``wall_time_s`` (time the worker spent on the case — the only
  variable that differs between two runs of one sweep); ``checksum`` (SHA-256 of the case's
  rows, :func:`case_checksum`);
* ``channels.<name>`` (case, ``<name>.sample``) with ``channels.<name>.time`` [s]
  (and ``.angle`` [rad] for encoder channels), the case's samples first, NaN after;
  ``channels.<name>.length`` the samples stored, ``.samples_computed`` before the cut;
* ``state.<var>`` (case, state_time, shaft | mesh);
* ``indicators`` (case, component, indicator, block), ``revolutions`` (case, component),
  with ``component_kind``;
* verdict variables (:mod:`geardyn.sweep.verdicts`) when the spec asks for verdicts.

Every per-case variable is chunked one case per chunk. The driver alone writes: a case's rows
first, then its checksum, then its ``status`` (the commit mark: a case without status is
pending and is run again on resume, overwriting the same chunks). The store is created aside
and renamed into place, and zarr's local store writes each chunk file atomically (temporary
file + rename), so the store stays readable whenever the driver is killed. :func:`verify`
recomputes the checksums: a deleted chunk (it reads as NaN) or a damaged one (it does not
decode) names its case.
"""

from __future__ import annotations

import hashlib
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
from geardyn.sweep.layout import LABEL_DIMS

if TYPE_CHECKING:
    from geardyn.sweep.layout import Layout
    from geardyn.sweep.spec import Sweep

LAYOUT = "geardyn.sweep/2"
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


def create(path: str | Path, sweep: Sweep, layout: Layout) -> bool:
    """A new store for ``sweep`` with every per-case variable of ``layout`` (NaN or ``''``:
    metadata only), case coordinates, empty status, provenance attributes. False when another
    driver created the store at ``path`` first (then it is used as it is)."""
    import dask.array as da

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
    diag = sweep.spec.outputs.diagnosis is not None
    coords["seed"] = ("case", np.array([c.seed for c in sweep.cases], np.int64),
                      {"long_name": "run seed: the case config's diagnosis.record_seed (the "
                                    "record of geardyn diagnose)" if diag else
                                    "run seed: SeedSequence([sweep seed, case]) first word"})
    data = {
        "status": ("case", _strings([PENDING] * n),
                   {"long_name": "'' pending; ok / diverged / suspect / stopped / reversed "
                                 "(run status) or failed"}),
        "message": ("case", _strings([""] * n), {"long_name": "why a case is not ok"}),
        "wall_time_s": ("case", np.full(n, np.nan), {"units": "s",
                                                     "long_name": "worker time of the case"}),
        "checksum": ("case", _strings([""] * n),
                     {"long_name": "SHA-256 of the case's rows (every per-case variable and "
                                   "its message), written before its status"}),
    }
    enc: dict[str, Any] = {v: {"chunks": (1,)} for v in data}
    text = []
    for name, var in layout.variables.items():
        shape = (n, *(layout.sizes[d] for d in var.dims))
        if var.text:
            data[name] = (("case", *var.dims), np.full(shape, "", dtype=object), var.attrs)
            text.append(name)
        else:
            data[name] = (("case", *var.dims), da.full(shape, np.nan, chunks=(1, *shape[1:])),
                          var.attrs)
            enc[name] = {"fill_value": np.nan}
        enc.setdefault(name, {})["chunks"] = (1, *shape[1:])
    for d, (labels, attrs) in layout.coords.items():
        arr = _strings([str(x) for x in labels]) if d in LABEL_DIMS else np.asarray(labels)
        coords[d] = (d, arr, attrs)
    if "component" in layout.coords:
        coords["component_kind"] = ("component", _strings(
            [layout.component_kind.get(str(c), "") for c in layout.coords["component"][0]]),
            {"long_name": "kind of the component (shaft, wheel, bearing, sun, planet, ring)"})
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
        "seed_rule": ("seed = diagnosis.record_seed of the case config" if diag
                      else "seed = SeedSequence([sweep_seed, case]).generate_state(1)[0]"),
        "combine": sweep.spec.sweep.combine,
        "axes": json.dumps([a.name for a in sweep.axes]),
        "case_variables": json.dumps(sorted(layout.variables)),
        "case_text_variables": json.dumps(sorted(text)),
    }
    # written aside and renamed: a store at ``path`` is always complete
    tmp = p.with_name(f".{p.name}.creating-{uuid.uuid4().hex[:8]}")
    try:
        _to_zarr(ds, tmp, mode="w-", encoding=enc, compute=False)  # numpy parts written
        try:
            os.rename(tmp, p)
        except OSError:
            if p.exists():  # another driver's store arrived first: use it
                return False
            raise
        return True
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
    layout = ds.attrs.get("geardyn_layout")
    if layout == "geardyn.sweep/1":
        raise InputError(f"'{p}' is a sweep store of an older geardyn (layout {layout!r}: "
                         "channels sized by the first case written; no checksums); give a new "
                         "--out to run the sweep again")
    if layout != LAYOUT:
        raise InputError(f"'{p}' is not a geardyn sweep store (layout "
                         f"{layout!r}, expected {LAYOUT!r})")
    return ds


def open_dataset(path: str | Path) -> xr.Dataset:
    """A data set geardyn wrote, as xarray: a sweep data set (``geardyn sweep ... --out
    PATH``, a Zarr folder) lazily loaded (dask), ``status``, ``message``, string coordinates
    and ``verdict`` as Python strings; or a run result (``geardyn simulate ... --out
    run.nc``, a NetCDF file in the layout of docs/results.md)."""
    p = Path(path)
    if p.is_file():
        try:
            return xr.open_dataset(p)
        except (OSError, ValueError) as exc:
            raise InputError(f"'{p}' is neither a sweep store (a folder) nor a readable "
                             f"NetCDF result file: {exc}") from None
    ds = open_store(path)
    for name in list(ds.variables):
        v = ds[name]
        if v.dtype.kind in ("T", "O", "U"):
            ds[name] = v.copy(data=np.asarray(v.values, dtype=object))
    return ds



#: Per-case variable every case writes besides the layout's, in the checksum (``wall_time_s``
#: is left out: it is the one variable that differs between two runs of a sweep, and the
#: checksum, like every other variable, is the same).
CASE_META = ("message",)


def _canonical(values: Any, text: bool) -> bytes:
    """Bytes of a case's row for the checksum: strings as UTF-8 (NUL-separated), numbers as
    little-endian float64 with every NaN the same bit pattern."""
    if text:
        return "\0".join(str(x) for x in np.asarray(values, dtype=object).ravel()).encode()
    a = np.asarray(values, dtype="<f8")
    a = np.where(np.isnan(a), np.nan, a)
    return np.ascontiguousarray(a).tobytes()


def case_checksum(rows: dict[str, tuple[Any, bool]]) -> str:
    """SHA-256 over the rows of one case (name → (values, is text)), names in sorted order."""
    h = hashlib.sha256()
    for name in sorted(rows):
        values, text = rows[name]
        h.update(name.encode() + b"\0")
        h.update(_canonical(values, text))
        h.update(b"\1")
    return "sha256:" + h.hexdigest()


class Writer:
    """Writes cases into the store at ``path`` through zarr (one chunk per case and
    variable): every per-case variable of the layout (NaN or ``''`` where the case has no
    value), its message and wall time, its checksum, then its status (the commit mark)."""

    def __init__(self, path: str | Path) -> None:
        import zarr

        self.path = Path(path)
        ds = _open(self.path)
        self.sizes = dict(ds.sizes)
        self.variables = json.loads(ds.attrs["case_variables"])
        self.text = set(json.loads(ds.attrs["case_text_variables"]))
        self.dims = {n: tuple(ds[n].dims[1:]) for n in self.variables}
        self.labels = {d: {str(x): k for k, x in enumerate(ds[d].values)}
                       for d in LABEL_DIMS if d in ds.coords}
        self.group = zarr.open_group(str(self.path), mode="r+")

    def _aligned(self, values: np.ndarray, dims: tuple[str, ...], cds: dict[str, Any]
                 ) -> tuple[np.ndarray, list[str]]:
        """``values`` on the store's grid of ``dims`` (labels matched, samples NaN-padded);
        labels the store lacks are dropped and returned."""
        v = np.asarray(values, float)
        if not dims:
            return v.reshape(()), []
        out = np.full([self.sizes[d] for d in dims], np.nan)
        dropped: list[str] = []
        src: list[np.ndarray] = []
        dst: list[np.ndarray] = []
        for d, n in zip(dims, np.shape(v), strict=True):
            if d in cds and d in self.labels:
                have = self.labels[d]
                lab = [str(x) for x in cds[d]]
                keep = [k for k, x in enumerate(lab) if x in have]
                dropped += [f"{d} {x}" for x in lab if x not in have]
                src.append(np.array(keep, int))
                dst.append(np.array([have[lab[k]] for k in keep], int))
            else:
                m = min(n, self.sizes[d])
                if n > self.sizes[d]:
                    dropped.append(f"{d} samples {self.sizes[d]}…{n - 1}")
                src.append(np.arange(m))
                dst.append(np.arange(m))
        out[np.ix_(*dst)] = v[np.ix_(*src)]
        return out, dropped

    def rows(self, index: int, result: dict[str, Any]) -> tuple[dict[str, tuple[Any, bool]],
                                                                  list[str]]:
        """Every per-case row of ``result`` on the store's grid, and what did not fit."""
        dropped: list[str] = []
        rows: dict[str, tuple[Any, bool]] = {}
        arrays = result.get("arrays", {})
        for name in self.variables:
            dims = self.dims[name]
            if name in self.text:
                shape = [self.sizes[d] for d in dims]
                if name in arrays and not dims:  # a case's text value (diagnosis.*)
                    rows[name] = (np.asarray(str(arrays[name][0]), dtype=object), True)
                else:  # filled after the cases (verdicts)
                    rows[name] = (np.full(shape, "", dtype=object), True)
                continue
            if name in arrays:
                values, _attrs, rdims, cds = arrays[name]
                if tuple(rdims) != dims:
                    dropped.append(f"{name} (dims {tuple(rdims)}, store {dims})")
                    arr = np.full([self.sizes[d] for d in dims], np.nan)
                else:
                    arr, d = self._aligned(values, dims, cds)
                    dropped += d
            else:
                arr = np.full([self.sizes[d] for d in dims], np.nan)
            rows[name] = (arr, False)
        dropped += [n for n in arrays if n not in self.variables]
        return rows, dropped

    def write_case(self, index: int, result: dict[str, Any]) -> None:
        """Write one case's rows, message, wall time and checksum, then its status (the
        commit mark: a case is stored whole or is pending)."""
        rows, dropped = self.rows(index, result)
        message = str(result["message"])
        if dropped:
            message += ("; " if message else "") + "not stored (not in the store's layout): " \
                + ", ".join(sorted(set(dropped))[:10])
        rows["message"] = (np.array(message, dtype=object), True)
        self.group["wall_time_s"][index] = float(result.get("wall_time_s", np.nan))
        for name, (values, text) in rows.items():
            if name == "message":
                self.group[name][index] = message
            elif text and np.ndim(values) == 0:
                self.group[name][index] = str(values)
            elif text:
                self.group[name][index] = np.asarray(values, dtype=object).astype(str)
            else:
                self.group[name][index] = values
        self.group["checksum"][index] = case_checksum(rows)
        self.group["status"][index] = str(result["status"])


def mark_pending(path: str | Path, cases: list[int]) -> None:
    """Set ``cases`` pending (damaged ones, or failed ones run again) before they run: a case
    being rewritten never carries an old status."""
    if not cases:
        return
    import zarr

    group = zarr.open_group(str(Path(path)), mode="r+")
    for i in cases:
        group["status"][i] = PENDING


#: Cases read together by :func:`verify` (zarr fetches their chunks concurrently).
VERIFY_BATCH = 32


def verify(path: str | Path, cases: list[int] | None = None) -> dict[int, str]:
    """Cases whose stored data no longer match their checksum (a deleted or damaged chunk):
    case index → what is wrong. Only cases with a status are checked (pending ones have
    nothing to check); a status chunk that cannot be read counts as damaged. Cases are read
    :data:`VERIFY_BATCH` at a time, case by case where a batch does not decode."""
    import zarr

    p = Path(path)
    ds = _open(p)
    variables = [*json.loads(ds.attrs["case_variables"]), *CASE_META, "checksum"]
    text = set(json.loads(ds.attrs["case_text_variables"])) | {"message", "checksum"}
    group = zarr.open_group(str(p), mode="r")
    status, unreadable = _statuses(group, ds.sizes["case"])
    damaged = {i: f"status unreadable ({e})" for i, e in unreadable.items()}
    todo = [i for i in (range(ds.sizes["case"]) if cases is None else cases)
            if i not in damaged and status[i] != PENDING]
    for start in range(0, len(todo), VERIFY_BATCH):
        batch = todo[start:start + VERIFY_BATCH]
        lo, hi = batch[0], batch[-1] + 1
        rows: dict[int, dict[str, tuple[Any, bool]]] = {i: {} for i in batch}
        for name in variables:
            is_text = name in text
            try:
                block = group[name][lo:hi]
                values = {i: block[i - lo] for i in batch}
            except Exception:  # noqa: BLE001 - a damaged chunk in the batch: case by case
                values = {}
                for i in batch:
                    if i in damaged:
                        continue
                    try:
                        values[i] = group[name][i]
                    except Exception as exc:  # noqa: BLE001 - any decoding error is damage
                        damaged[i] = f"'{name}' unreadable ({type(exc).__name__}: {exc})"
            for i, v in values.items():
                rows[i][name] = (np.asarray(v, dtype=object) if is_text
                                 else np.asarray(v, dtype=float), is_text)
        for i in batch:
            if i in damaged:
                continue
            stored = str(rows[i].pop("checksum")[0])
            if stored != case_checksum(rows[i]):
                damaged[i] = ("checksum mismatch: a chunk of the case was deleted or changed"
                              if stored else "no checksum (its chunk lost)")
    return damaged


def _statuses(group: Any, n: int) -> tuple[np.ndarray, dict[int, str]]:
    """Status of every case, reading chunk by chunk when the whole array cannot be read;
    unreadable ones are pending (and listed)."""
    try:
        return np.asarray(group["status"][:], dtype=object), {}
    except Exception:  # noqa: BLE001 - a damaged status chunk: find it
        pass
    out = np.full(n, PENDING, dtype=object)
    bad: dict[int, str] = {}
    for i in range(n):
        try:
            out[i] = str(group["status"][i])
        except Exception as exc:  # noqa: BLE001
            bad[i] = f"{type(exc).__name__}: {exc}"
    return out, bad


def statuses(path: str | Path) -> np.ndarray:
    """Status of every case (``''`` pending, and for a status chunk that cannot be read)."""
    import zarr

    p = Path(path)
    n = _open(p).sizes["case"]
    return _statuses(zarr.open_group(str(p), mode="r"), n)[0]

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
