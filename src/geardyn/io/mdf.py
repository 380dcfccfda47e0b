"""ASAM MDF 4 (and 3) files through :mod:`asammdf`: every non-master channel with its units
and a sample rate from its (uniform) timestamps; the measurement start as the timestamp."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geardyn.io.raw import RawChannel, RawRecord, uniform_rate


def read_mdf(p: Path) -> RawRecord:
    """Channels of an MDF file (module docstring)."""
    from asammdf import MDF

    chans: dict[str, RawChannel] = {}
    with MDF(str(p)) as mdf:
        stamp = str(mdf.header.start_time) if getattr(mdf, "header", None) else None
        for sig in mdf.iter_channels(skip_master=True):
            name = str(sig.name)
            if name in chans:
                name = f"{name}#{len(chans)}"
            t = np.asarray(sig.timestamps, float)
            fs = uniform_rate(t, f"{p}: timestamps of '{name}'") if t.size > 1 else None
            chans[name] = RawChannel(name, np.asarray(sig.samples, float), fs,
                                     str(sig.unit or ""), float(t[0]) if t.size else 0.0)
    return RawRecord(p, chans, None, stamp, [], "mdf")
