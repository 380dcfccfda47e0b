"""Universal File Format datasets 58 (ASCII) and 58b (binary) through :mod:`pyuff`.

Each function record of type 58 is a channel named by its ``id1`` text (else
``<response node><direction>``, else its index); uniform abscissa spacing gives the sample rate
(``abscissa_inc`` or the ``x`` values), ``ordinate_axis_units_lab`` the units."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geardyn.errors import InputError
from geardyn.io.raw import RawChannel, RawRecord, uniform_rate


def read_uff(p: Path) -> RawRecord:
    """Type-58 records of a UFF file (module docstring)."""
    import pyuff

    u = pyuff.UFF(str(p))
    types = list(u.get_set_types())
    idx = [i for i, t in enumerate(types) if int(t) == 58]
    if not idx:
        raise InputError(f"{p}: no dataset 58 (function record) in the file (dataset types: "
                         f"{sorted({int(t) for t in types})})")
    sets = u.read_sets(idx)
    sets = [sets] if isinstance(sets, dict) else list(sets)
    chans: dict[str, RawChannel] = {}
    for k, s in zip(idx, sets, strict=True):
        name = str(s.get("id1", "")).strip()
        if not name or name in chans:
            node = s.get("rsp_node")
            name = f"{node}{_dir(s.get('rsp_dir'))}" if node is not None else str(k)
        if name in chans:
            name = str(k)
        y = np.asarray(s["data"])
        if np.iscomplexobj(y):
            raise InputError(f"{p}: dataset 58 '{name}' holds complex values (a spectrum or "
                             "FRF, function type {s.get('func_type')}); a time record is needed")
        x = np.asarray(s.get("x", []), float)
        inc = float(s.get("abscissa_inc", 0.0) or 0.0)
        if x.size == y.size and x.size > 1:
            fs = uniform_rate(x, f"{p}: abscissa of '{name}'")
            t0 = float(x[0])
        else:
            fs, t0 = (1.0 / inc if inc > 0 else None), float(s.get("abscissa_min", 0.0))
        units = str(s.get("ordinate_axis_units_lab", "")).strip()
        chans[name] = RawChannel(name, y.astype(float), fs, units, t0,
                                 attrs={"func_type": int(s.get("func_type", 0))})
    return RawRecord(p, chans, None, None, [], "uff")


def _dir(d) -> str:  # noqa: ANN001
    names = {1: "+X", 2: "+Y", 3: "+Z", -1: "-X", -2: "-Y", -3: "-Z"}
    try:
        return names.get(int(d), "")
    except (TypeError, ValueError):
        return ""
