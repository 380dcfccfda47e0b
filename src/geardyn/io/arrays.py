"""NumPy arrays: ``.npy`` (one array: a vector, or samples × channels) and ``.npz`` (named
arrays: 1-D channels, 2-D samples × channels as ``name[j]``, a scalar sample rate under one of
:data:`geardyn.io.raw.FS_KEYS`, a time vector [s], ``pulse_times`` [s] as an event channel).
NumPy stores no units or rate: the channel mapping gives them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geardyn.errors import InputError
from geardyn.io.raw import FS_KEYS, RawChannel, RawRecord, is_time_name, uniform_rate


def _columns(name: str, a: np.ndarray, src: str) -> dict[str, np.ndarray]:
    if a.ndim == 1:
        return {name or "0": a}
    if a.ndim == 2:
        if a.shape[0] < a.shape[1]:
            raise InputError(f"{src}: array '{name}' has shape {a.shape}; expected samples × "
                             "channels (more rows than columns): transpose it")
        return {f"{name}[{j}]" if name else str(j): a[:, j] for j in range(a.shape[1])}
    raise InputError(f"{src}: array '{name}' has {a.ndim} dimensions; expected 1 or 2")


def read_numpy(p: Path, time_channel: str | None = None) -> RawRecord:
    """Channels of an ``.npy`` or ``.npz`` file (module docstring)."""
    src = str(p)
    if p.suffix.lower() == ".npy":
        a = np.load(p, allow_pickle=False, mmap_mode="r")
        cols = _columns("", a, src)
        return RawRecord(p, {n: RawChannel(n, v) for n, v in cols.items()}, format="numpy")
    fs = None
    chans: dict[str, RawChannel] = {}
    tname, t = None, None
    with np.load(p, allow_pickle=False) as z:
        for key in z.files:
            a = z[key]
            if a.ndim == 0 or a.size == 1:
                if key in FS_KEYS:
                    fs = float(a)
                continue
            if key == time_channel or (time_channel is None and is_time_name(key)):
                tname, t = key, np.asarray(a, float).ravel()
                continue
            if key == "pulse_times":
                chans[key] = RawChannel(key, np.asarray(a, float).ravel(), None, "s",
                                        attrs={"events": True})
                continue
            for n, v in _columns(key, a, src).items():
                chans[n] = RawChannel(n, np.asarray(v, float))
    if t is not None:
        rate = uniform_rate(t, f"{src}: time array '{tname}'")
        if fs is not None and abs(rate - fs) > 1e-6 * fs:
            raise InputError(f"{src}: the time array '{tname}' gives {rate:g} Hz but the file's "
                             f"sample rate is {fs:g} Hz")
        fs = rate
    for c in chans.values():
        if not c.attrs.get("events"):
            c.fs = fs
            c.t0 = float(t[0]) if t is not None else 0.0
    if not chans:
        raise InputError(f"{src}: no array to read (keys: {', '.join(sorted(chans))})")
    return RawRecord(p, chans, tname, None, [], "numpy")
