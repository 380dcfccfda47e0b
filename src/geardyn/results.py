"""One result layout for every dynamic model (documented in ``docs/results.md``).

A simulation result is an :class:`xarray.Dataset` with

* coordinates ``time`` [s], ``shaft`` (mechanism link names and model bodies) and ``mesh``;
* ``angle`` (time, shaft) [rad], ``speed`` (time, shaft) [rad/s], ``speed_rpm`` (time, shaft)
  [rpm]: rotation of every shaft, signed in the positive sense of its link (rigid-body motion
  and deformation together);
* ``mesh_force`` (time, mesh) [N]; model-specific variables may follow (``q``, ``v``,
  ``mesh_deflection``, ``bearing_force`` …);
* sensor channels ``sensors.<name>``: 1-D variables, each on its own dimension
  (``sensors.<name>.time`` [s] for time-sampled channels, ``sensors.<name>.angle`` [rad] with
  ``sensors.<name>.time`` along it for angle-sampled channels such as encoder IAS,
  ``sensors.<name>.pulse`` for tacho pulse times), with attrs ``units``, ``long_name``,
  ``sensor_kind``, ``sampling``, ``shaft`` (the shaft the channel is referenced to) and the
  sampling parameters;
* attrs ``geardyn_layout``, ``model``, ``status`` (``ok``, ``diverged``, ``interrupted``,
  ``suspect``, ``stopped``, ``reversed``: docs/robustness.md), ``diagnosis``, ``seed``,
  ``reference_shaft``.

This module reads the layout (channels, shaft angles) and checks it; builders in the model
packages write it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from geardyn.errors import InputError

LAYOUT = "geardyn.result/1"
PREFIX = "sensors."
RAD_S_TO_RPM = 60.0 / (2.0 * np.pi)


@dataclass
class Channel:
    """One sensor channel of a result.

    ``sampling``: ``time`` (uniform in time, ``sample_rate_hz``), ``angle`` (one sample per
    encoder interval, ``angle`` [rad] of the encoder shaft) or ``events`` (``values`` are pulse
    times [s]). ``time`` [s] is always given: sample times, or the pulse times themselves.
    """

    name: str
    kind: str
    values: np.ndarray
    units: str
    shaft: str
    sampling: str
    time: np.ndarray
    angle: np.ndarray | None = None
    sample_rate_hz: float | None = None
    pulses_per_rev: int | None = None
    attrs: dict = field(default_factory=dict)


def is_result(ds: xr.Dataset) -> bool:
    """True for a dataset in the geardyn result layout."""
    return str(ds.attrs.get("geardyn_layout", "")) == LAYOUT


def channels(ds: xr.Dataset) -> list[str]:
    """Names of the sensor channels (without the ``sensors.`` prefix)."""
    return [str(v)[len(PREFIX):] for v in ds.data_vars if str(v).startswith(PREFIX)]


def channel(ds: xr.Dataset, name: str) -> Channel:
    """The sensor channel ``name`` (with or without the ``sensors.`` prefix)."""
    key = name if name.startswith(PREFIX) else PREFIX + name
    if key not in ds.data_vars:
        have = channels(ds)
        raise InputError(
            f"channel: '{name}' not found; the result has channels "
            f"{', '.join(have) if have else '(none: add [[sensors]] to the config)'}"
        )
    da = ds[key]
    if da.ndim != 1:
        raise InputError(f"channel '{name}': expected a 1-D channel, got dims {da.dims}")
    a = dict(da.attrs)
    dim = da.dims[0]
    sampling = str(a.get("sampling", "time"))
    vals = np.asarray(da.values, dtype=float)
    angle = None
    if sampling == "events":
        time = vals
    elif sampling == "angle":
        angle = np.asarray(da[dim].values, dtype=float)
        tkey = f"{key}.time"
        if tkey not in da.coords:
            raise InputError(f"channel '{name}': angle-sampled channel without '{tkey}'")
        time = np.asarray(da[tkey].values, dtype=float)
    else:
        time = np.asarray(da[dim].values, dtype=float)
    fs = a.get("sample_rate_hz")
    ppr = a.get("pulses_per_rev")
    return Channel(
        name=key[len(PREFIX):], kind=str(a.get("sensor_kind", "")), values=vals,
        units=str(a.get("units", "")), shaft=str(a.get("shaft", "")), sampling=sampling,
        time=time, angle=angle, sample_rate_hz=None if fs is None else float(fs),
        pulses_per_rev=None if ppr is None else int(ppr), attrs=a,
    )


def shafts(ds: xr.Dataset) -> list[str]:
    """Shaft names of a result."""
    if "shaft" not in ds.coords:
        raise InputError("result: no 'shaft' coordinate (not a geardyn simulation result)")
    return [str(s) for s in ds["shaft"].values]


def shaft_angle(ds: xr.Dataset, shaft: str) -> tuple[np.ndarray, np.ndarray]:
    """``(time [s], angle [rad])`` of ``shaft``."""
    names = shafts(ds)
    if shaft not in names:
        raise InputError(f"shaft: '{shaft}' not in the result (shafts: {', '.join(names)})")
    return (np.asarray(ds["time"].values, float),
            np.asarray(ds["angle"].sel(shaft=shaft).values, float))


def shaft_variables(time: np.ndarray, names: list[str], angle: np.ndarray, speed: np.ndarray,
                    speed_rpm: np.ndarray | None = None) -> dict[str, tuple]:
    """``angle``/``speed``/``speed_rpm`` variables (time, shaft) with units and long names
    (``speed_rpm``: ``speed`` × :data:`RAD_S_TO_RPM` when the caller has it already)."""
    if speed_rpm is None:
        speed_rpm = speed * RAD_S_TO_RPM
    return {
        "angle": (("time", "shaft"), angle,
                  {"units": "rad", "long_name": "shaft rotation angle"}),
        "speed": (("time", "shaft"), speed,
                  {"units": "rad/s", "long_name": "shaft angular speed"}),
        "speed_rpm": (("time", "shaft"), speed_rpm,
                      {"units": "rpm", "long_name": "shaft speed"}),
    }


def finish(ds: xr.Dataset, model: str, reference_shaft: str, seed: int | None = None,
           attrs: dict | None = None) -> xr.Dataset:
    """Stamp the layout attributes on a model result (status kept; ``ok`` if absent)."""
    ds.attrs.setdefault("status", "ok")
    ds.attrs.setdefault("diagnosis", "")
    ds.attrs.update({"geardyn_layout": LAYOUT, "model": model,
                     "reference_shaft": reference_shaft,
                     "seed": -1 if seed is None else int(seed), **(attrs or {})})
    import geardyn

    ds.attrs["geardyn_version"] = geardyn.__version__
    return ds


def check_rotation(ds: xr.Dataset, shafts_seen: list[str]) -> list[str]:
    """Status check of the shafts a sensor looks at: a shaft that stops or turns backwards
    while it is measured is reported (status ``stopped`` / ``reversed``) and warned about.

    Returns the problems found; ``ds.attrs['status']`` and ``['diagnosis']`` are updated
    (a diverged run keeps ``diverged``).
    """
    problems: list[str] = []
    status = None
    names = shafts(ds)
    for s in dict.fromkeys(shafts_seen):
        if s not in names:
            continue
        w = np.asarray(ds["speed"].sel(shaft=s).values, float)
        if w.size == 0:
            continue
        sign = np.sign(np.median(w)) or 1.0
        ws = sign * w
        tol = 1e-3 * max(float(np.max(np.abs(w))), 1e-12)
        t = np.asarray(ds["time"].values, float)
        if np.any(ws < -tol):
            i = int(np.argmax(ws < -tol))
            problems.append(f"shaft '{s}' turns backwards from t = {t[i]:.6g} s")
            status = "reversed"
        elif np.any(np.abs(w) <= tol):
            i = int(np.argmax(np.abs(w) <= tol))
            problems.append(f"shaft '{s}' stops at t = {t[i]:.6g} s")
            status = status or "stopped"
    if problems:
        if ds.attrs.get("status", "ok") == "ok":
            ds.attrs["status"] = status
        msg = "; ".join(problems) + " (sensors referenced to it are not meaningful there)"
        ds.attrs["diagnosis"] = (str(ds.attrs.get("diagnosis", "")) + " " + msg).strip()
        warnings.warn(msg, stacklevel=2)
    return problems


def to_netcdf(ds: xr.Dataset, path) -> None:  # noqa: ANN001 - str | Path
    """Write a result as NetCDF4 (h5netcdf); attrs that NetCDF cannot hold become strings.

    The file is written under a temporary name in the same directory and renamed
    (:func:`geardyn.checkpoint.write_atomic`): a run killed while writing leaves no corrupt
    file at ``path``."""
    from geardyn.checkpoint import write_atomic

    out = ds.copy()
    out.attrs = {k: _attr(v) for k, v in ds.attrs.items()}
    for v in out.variables.values():
        v.attrs = {k: _attr(x) for k, x in v.attrs.items()}
    write_atomic(path, lambda tmp: out.to_netcdf(tmp, engine="h5netcdf"))


def _attr(v):  # noqa: ANN001, ANN202
    if isinstance(v, bool | np.bool_):
        return int(v)
    if isinstance(v, str | int | float | np.integer | np.floating):
        return v
    if isinstance(v, np.ndarray | list | tuple):
        a = np.asarray(v)
        if a.dtype.kind in "iuf":
            return a
        return ", ".join(str(x) for x in a.ravel())
    if v is None:
        return ""
    return str(v)
