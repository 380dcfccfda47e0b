"""HDF5 and NetCDF files of any layout.

HDF5 (:mod:`h5py`): every numeric dataset is a channel named by its path without the leading
``/`` (``group/acc``; samples × channels datasets as ``path[j]``), or only the paths the
mapping names (``sources``). Per dataset, its attributes give the rate (``fs``,
``sample_rate``… or an interval ``dt``/``wf_increment``), the units (``units``/``unit``) and
the start (``t0``); a time dataset (``time``/``t``, or ``time_channel``) of the same length
gives the rate of the datasets beside it. Attributes of the parent groups apply too.

NetCDF 3/4 (:mod:`xarray`): every 1-D data variable; the rate from an attribute or from its
time coordinate, the units from ``units``; a ``pulse_times`` variable [s] is an event channel.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geardyn.errors import InputError
from geardyn.io.arrays import _columns
from geardyn.io.raw import (
    DT_KEYS,
    FS_KEYS,
    RawChannel,
    RawRecord,
    is_time_name,
    uniform_rate,
)


def _attr_text(v) -> str:  # noqa: ANN001
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, np.ndarray) and v.size == 1:
        return _attr_text(v.item())
    return str(v)


def _rate(attrs_chain: list, src: str) -> float | None:
    for attrs in attrs_chain:
        for k in FS_KEYS:
            if k in attrs:
                return float(np.asarray(attrs[k]).ravel()[0])
        for k in DT_KEYS:
            if k in attrs:
                dt = float(np.asarray(attrs[k]).ravel()[0])
                if dt <= 0:
                    raise InputError(f"{src}: attribute '{k}' = {dt:g} s is not a sample interval")
                return 1.0 / dt
    return None


def read_hdf5(p: Path, time_channel: str | None = None, sources: list[str] | None = None
              ) -> RawRecord:
    """Channels of an HDF5 file of any layout (module docstring)."""
    import h5py

    src = str(p)
    chans: dict[str, RawChannel] = {}
    times: dict[str, tuple[str, np.ndarray]] = {}
    wanted = {s.strip("/").split("[")[0] for s in sources} if sources else None
    stamp = None
    with h5py.File(p, "r") as f:
        found: list[tuple[str, h5py.Dataset]] = []
        f.visititems(lambda name, obj: found.append((name, obj))
                     if isinstance(obj, h5py.Dataset) else None)
        for k in ("timestamp", "start_time", "date"):
            if k in f.attrs:
                stamp = _attr_text(f.attrs[k])
        for name, ds in found:
            if ds.dtype.kind not in "iuf" or ds.ndim == 0 or ds.size < 2:
                continue
            parent = name.rsplit("/", 1)[0] if "/" in name else ""
            leaf = name.rsplit("/", 1)[-1]
            if name == (time_channel or "").strip("/") or (time_channel is None
                                                             and is_time_name(leaf)):
                times[parent] = (name, np.asarray(ds[()], float).ravel())
                continue
            if wanted and not {name, leaf} & wanted and any(
                    n in wanted or n.rsplit("/", 1)[-1] in wanted for n, _ in found):
                continue  # only the mapped datasets (when the mapping names any)
            chain = [ds.attrs]
            g = ds.parent
            while g is not None and g.name != "/":
                chain.append(g.attrs)
                g = g.parent
            chain.append(f.attrs)
            fs = _rate(chain, f"{src}: dataset '{name}'")
            units = next((_attr_text(a[u]) for a in chain for u in ("units", "unit",
                                                                      "unit_string") if u in a), "")
            t0 = float(np.asarray(ds.attrs.get("t0", 0.0)).ravel()[0])
            for n, col in _columns(name, np.asarray(ds[()]), src).items():
                chans[n] = RawChannel(n, np.asarray(col, float), fs, units, t0,
                                      attrs={"group": parent})
    tname = None
    for c in chans.values():
        tv = times.get(c.attrs["group"]) or times.get("")
        if tv is not None and tv[1].size == c.values.size:
            rate = uniform_rate(tv[1], f"{src}: time dataset '{tv[0]}'")
            if c.fs is not None and abs(rate - c.fs) > 1e-6 * c.fs:
                raise InputError(f"{src}: dataset '{c.name}': its rate attribute says "
                                 f"{c.fs:g} Hz, the time dataset '{tv[0]}' {rate:g} Hz")
            c.fs, c.t0, tname = rate, float(tv[1][0]), tv[0]
    if not chans:
        what = f" among {', '.join(sorted(wanted))}" if wanted else ""
        raise InputError(f"{src}: no numeric dataset{what} in the HDF5 file")
    return RawRecord(p, chans, tname, stamp, [], "hdf5")


def read_netcdf(p: Path, time_channel: str | None = None) -> RawRecord:
    """Channels of a NetCDF 3/4 file (module docstring)."""
    import xarray as xr

    with p.open("rb") as fh:
        magic = fh.read(8)
    if not (magic.startswith(b"CDF") or magic.startswith(b"\x89HDF")):
        raise InputError(f"{p}: not a NetCDF file (neither a NetCDF3 nor a NetCDF4/HDF5 header)")
    src = str(p)
    chans: dict[str, RawChannel] = {}
    with xr.open_dataset(p) as ds:
        stamp = _attr_text(ds.attrs["timestamp"]) if "timestamp" in ds.attrs else None
        tname = None
        for v in ds.data_vars:
            da = ds[v]
            name = str(v)
            if name == "pulse_times":
                chans[name] = RawChannel(name, np.asarray(da.values, float).ravel(), None, "s",
                                         attrs={"events": True})
                continue
            if da.ndim != 1 or da.dtype.kind not in "iuf":
                continue
            if name == time_channel or (time_channel is None and is_time_name(name)):
                continue
            fs = _rate([da.attrs, ds.attrs], f"{src}: variable '{name}'")
            dim = da.dims[0]
            t0 = 0.0
            if dim in da.coords and da[dim].dtype.kind in "iuf" and (
                    is_time_name(str(dim)) or str(dim).endswith(".time")):
                t = np.asarray(da[dim].values, float)
                rate = uniform_rate(t, f"{src}: time coordinate of '{name}'")
                if fs is not None and abs(rate - fs) > 1e-6 * fs:
                    raise InputError(f"{src}: variable '{name}': its rate attribute says "
                                     f"{fs:g} Hz, its time coordinate {rate:g} Hz")
                fs, t0, tname = rate, float(t[0]), str(dim)
            chans[name] = RawChannel(name, np.asarray(da.values, float), fs,
                                     str(da.attrs.get("units", "")), t0)
    if not chans:
        raise InputError(f"{src}: no 1-D numeric variable in the NetCDF file")
    return RawRecord(p, chans, tname, stamp, [], "netcdf")
