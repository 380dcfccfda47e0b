"""NI TDMS files through :mod:`nptdms`: every channel of every group, named
``group/channel`` (the channel name alone is accepted when unique); the sample interval from the
waveform property ``wf_increment`` [s], the start from ``wf_start_offset`` [s], the units from
``unit_string``, the timestamp from ``wf_start_time``."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geardyn.io.raw import RawChannel, RawRecord, is_time_name, uniform_rate


def read_tdms(p: Path) -> RawRecord:
    """Channels of a TDMS file (module docstring)."""
    from nptdms import TdmsFile

    f = TdmsFile.read(str(p))
    chans: dict[str, RawChannel] = {}
    stamp = None
    times: dict[str, np.ndarray] = {}
    for g in f.groups():
        for ch in g.channels():
            name = f"{g.name}/{ch.name}"
            props = ch.properties
            values = np.asarray(ch[:], dtype=float)
            if is_time_name(ch.name):
                times[g.name] = values
                continue
            inc = props.get("wf_increment")
            fs = 1.0 / float(inc) if inc else None
            if stamp is None and props.get("wf_start_time") is not None:
                stamp = str(np.datetime64(props["wf_start_time"], "us"))
            chans[name] = RawChannel(name, values, fs, str(props.get("unit_string", "")),
                                     float(props.get("wf_start_offset", 0.0)),
                                     attrs={"group": g.name})
    tname = None
    for c in chans.values():  # a time channel of the group gives the rate of the others
        t = times.get(c.attrs["group"])
        if c.fs is None and t is not None and t.size == c.values.size:
            c.fs, c.t0 = uniform_rate(t, f"{p}: time channel of group '{c.attrs['group']}'"), \
                float(t[0])
            tname = f"{c.attrs['group']}/time"
    return RawRecord(p, chans, tname, stamp, [], "tdms")
