"""The trend store: one Zarr group, one sub-group per record (layout ``geardyn.trend/1``).

``<store>/records/<key>``: an xarray data set with dimension ``row`` holding the record's
indicator table (``component``, ``kind``, ``indicator``, ``channel``, ``value``: the median over
blocks, dimensionless) and attributes ``file``, ``timestamp`` (ISO 8601), ``speed_rpm``,
``load_nm``, ``warnings``. ``key`` is the SHA-1 of the file's bytes (first 16 hex digits): a
record is added once, whatever its name or folder, and re-running adds nothing new.

Ctrl-C safety: a record is written under a temporary name inside the store and renamed into
place (one ``rename``: atomic on POSIX), with Ctrl-C held during the rename
(:func:`geardyn.sweep.runner._deferred_sigint`); an interrupted write leaves a temporary
group that is ignored and removed by the next run.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import uuid
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from geardyn.errors import InputError

LAYOUT = "geardyn.trend/1"
_MARK = "geardyn-trend.json"
_COLS = ("component", "kind", "indicator", "channel")


def record_key(path: str | Path) -> str:
    """SHA-1 of the file's bytes (16 hex digits)."""
    h = hashlib.sha1()
    with Path(path).open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()[:16]


class TrendStore:
    """A trend store at ``path`` (created on first use)."""

    def __init__(self, path: str | Path, create: bool = True, tidy: bool = True) -> None:
        """``tidy``: remove the temporary groups an interrupted write left (False for the
        writers of a running update, whose own temporary groups are in flight)."""
        self.path = Path(path)
        mark = self.path / _MARK
        if self.path.exists():
            if not mark.is_file():
                raise InputError(f"--store: '{self.path}' exists and is not a geardyn trend "
                                 "store; give a new path or an existing store")
            layout = json.loads(mark.read_text()).get("layout")
            if layout != LAYOUT:
                raise InputError(f"--store: '{self.path}' has layout {layout!r}, expected "
                                 f"{LAYOUT}")
        elif create:
            self.path.mkdir(parents=True)
            (self.path / "records").mkdir()
            mark.write_text(json.dumps({"layout": LAYOUT}))
        else:
            raise InputError(f"--store: '{self.path}' does not exist")
        if tidy:
            for tmp in (self.path / "records").glob(".tmp-*"):  # an interrupted write
                shutil.rmtree(tmp, ignore_errors=True)

    def keys(self) -> set[str]:
        return {p.name for p in (self.path / "records").iterdir() if not p.name.startswith(".")}

    def add(self, key: str, table: pd.DataFrame, info: dict[str, Any]) -> bool:
        """Store a record's indicator table (median over blocks); False if already there."""
        from geardyn.sweep.runner import _deferred_sigint

        final = self.path / "records" / key
        if final.exists():
            return False
        g = table.groupby(list(_COLS), sort=False)["value"].median().reset_index()
        ds = xr.Dataset(
            {c: ("row", np.asarray(g[c].astype(str), dtype=object)) for c in _COLS}
            | {"value": ("row", g["value"].to_numpy(float), {"units": "1", "long_name":
                                                             "indicator (median over blocks)"})},
            attrs={k: ("" if v is None else v) for k, v in info.items()})
        tmp = self.path / "records" / f".tmp-{uuid.uuid4().hex}"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # zarr v3 notes on string dtypes
            ds.to_zarr(tmp, consolidated=False)
        with _deferred_sigint():
            os.rename(tmp, final)
        return True

    def table(self) -> pd.DataFrame:
        """Every stored record as long rows: ``key``, ``file``, ``timestamp`` (datetime),
        ``speed_rpm``, ``load_nm``, the key columns and ``value``; sorted by time."""
        parts = []
        for key in sorted(self.keys()):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                ds = xr.open_zarr(self.path / "records" / key, consolidated=False).load()
            df = pd.DataFrame({c: [str(v) for v in ds[c].values.tolist()] for c in _COLS})
            df["value"] = ds["value"].values
            df["key"] = key
            for a in ("file", "timestamp", "speed_rpm", "load_nm", "warnings"):
                df[a] = ds.attrs.get(a, "")
            parts.append(df)
        if not parts:
            return pd.DataFrame(columns=["key", "file", "timestamp", *_COLS, "value"])
        out = pd.concat(parts, ignore_index=True)
        out["timestamp"] = pd.to_datetime(out["timestamp"], format="ISO8601")
        return out.sort_values(["timestamp", "key"], kind="stable").reset_index(drop=True)
