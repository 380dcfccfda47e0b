"""Audio files (WAV, FLAC) through :mod:`soundfile` (libsndfile).

Integer PCM is returned as a fraction of digital full scale (``int16`` / 32768, the soundfile
convention, so that ±1 is full scale); float files as stored. Either way the file states no
physical unit: the channel mapping's ``full_scale`` (the quantity at digital 1.0, e.g.
``"5 V"``) and ``sensitivity`` turn the values into a physical quantity
(:mod:`geardyn.io.record`). Channels are named ``0``, ``1`` … in file order.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geardyn.io.raw import RawChannel, RawRecord


def read_audio(p: Path) -> RawRecord:
    """Every channel of a WAV/FLAC file, with the file's sample rate."""
    import soundfile as sf

    data, rate = sf.read(str(p), dtype="float64", always_2d=True)
    info = sf.info(str(p))
    note = (f"{info.format} {info.subtype}, {info.channels} channel(s) at {rate} Hz; values are "
            "fractions of digital full scale (set full_scale and sensitivity in the mapping)")
    chans = {str(i): RawChannel(str(i), np.ascontiguousarray(data[:, i]), float(rate), "",
                                attrs={"full_scale_fraction": True, "subtype": info.subtype})
             for i in range(data.shape[1])}
    return RawRecord(p, chans, None, None, [note], "audio")
