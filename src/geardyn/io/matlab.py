"""MATLAB MAT files: v5 (and v4/v6) through :func:`scipy.io.loadmat`, v7.3 (HDF5) through
:mod:`h5py` (MATLAB stores arrays column-major, so an h5py dataset of shape (1, n) is the
MATLAB column n × 1).

Numeric variables become channels (1-D, or samples × channels as ``name[j]``); a scalar under
one of :data:`geardyn.io.raw.FS_KEYS` is the sample rate [Hz]; a variable named ``t``/``time``
(or ``time_channel``) is the time vector [s]. MAT files carry no units: the mapping gives them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geardyn.errors import InputError
from geardyn.io.arrays import _columns
from geardyn.io.raw import FS_KEYS, RawChannel, RawRecord, is_time_name, uniform_rate


def _variables_v5(p: Path) -> dict[str, np.ndarray]:
    from scipy.io import loadmat

    m = loadmat(str(p), squeeze_me=True, mat_dtype=False)
    return {k: v for k, v in m.items() if not k.startswith("__")
            and isinstance(v, np.ndarray | int | float) and np.asarray(v).dtype.kind in "iufb"}


def _variables_v73(p: Path) -> dict[str, np.ndarray]:
    import h5py

    out: dict[str, np.ndarray] = {}
    with h5py.File(p, "r") as f:
        for k, ds in f.items():
            if not isinstance(ds, h5py.Dataset) or k.startswith("#"):
                continue
            cls = ds.attrs.get("MATLAB_class", b"double")
            cls = cls.decode() if isinstance(cls, bytes) else str(cls)
            if cls in ("char", "cell", "struct", "function_handle") or ds.dtype.kind not in "iufb":
                continue
            a = np.asarray(ds[()]).T  # column-major
            out[k] = np.squeeze(a)
    return out


def read_mat(p: Path, time_channel: str | None = None) -> RawRecord:
    """Channels of a MAT file (module docstring)."""
    from scipy.io.matlab import matfile_version

    src = str(p)
    major, _ = matfile_version(str(p))
    variables = _variables_v73(p) if major == 2 else _variables_v5(p)
    version = "v7.3 (HDF5)" if major == 2 else "v5"
    fs = None
    tname, t = None, None
    chans: dict[str, RawChannel] = {}
    for k, v in variables.items():
        a = np.asarray(v)
        if a.size == 1:
            if k in FS_KEYS:
                fs = float(a)
            continue
        if k == time_channel or (time_channel is None and is_time_name(k)):
            tname, t = k, a.astype(float).ravel()
            continue
        for n, col in _columns(k, a, src).items():
            chans[n] = RawChannel(n, np.asarray(col, float))
    if not chans:
        raise InputError(f"{src}: MAT {version} file without a numeric array "
                         f"(variables: {', '.join(variables) or 'none'})")
    if t is not None:
        rate = uniform_rate(t, f"{src}: time variable '{tname}'")
        if fs is not None and abs(rate - fs) > 1e-6 * fs:
            raise InputError(f"{src}: the time variable '{tname}' gives {rate:g} Hz but the "
                             f"file's sample rate is {fs:g} Hz")
        fs = rate
    for c in chans.values():
        c.fs, c.t0 = fs, (float(t[0]) if t is not None else 0.0)
    return RawRecord(p, chans, tname, None, [f"MAT {version}"], "mat")
