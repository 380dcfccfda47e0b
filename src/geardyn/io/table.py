"""Delimited text tables (CSV, TSV, whitespace): delimiter, decimal comma and header detected.

The first 64 KiB are examined (comment lines starting with ``#`` or ``%`` skipped): each
candidate delimiter (``,`` ``;`` tab ``|`` space; :class:`csv.Sniffer`'s choice tried first)
with each decimal mark (``.``, and ``,`` unless ``,`` delimits) is a *reading* of the file; a
reading is valid when every line has the same number of fields and every data field is a
number. One valid reading is used; none is an error (mixed delimiters, text in a data line),
several that give different tables are an error naming the columns of each (give
``delimiter``/``decimal``). The first line is a header when one of its fields is not a number
(then a second non-numeric line is a units row); units also come from a header written
``name [unit]`` or ``name (unit)``. The file is then read by :func:`pandas.read_csv`.

A time column (named ``time``/``t``/``Time [s]``…, named by ``time_channel``, or a first
column increasing in uniform steps) gives the sample rate and is never a signal.
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from geardyn.errors import InputError
from geardyn.io.raw import (
    RawChannel,
    RawRecord,
    is_time_name,
    is_uniform_time,
    split_unit,
    uniform_rate,
)

_SAMPLE = 1 << 16
_CANDIDATES = (",", ";", "\t", "|", " ")
_NUM = {".": re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$"),
        ",": re.compile(r"^[+-]?(\d+(,\d*)?|,\d+)([eE][+-]?\d+)?$")}
_SPECIAL = {"nan", "inf", "+inf", "-inf", "infinity", "-infinity", ""}
_NAMES = {",": "comma", ";": "semicolon", "\t": "tab", "|": "pipe", " ": "whitespace"}


def _lines(p: Path) -> list[str]:
    with p.open("rb") as fh:
        raw = fh.read(_SAMPLE + 1)
    truncated = len(raw) > _SAMPLE
    try:
        text = raw[:_SAMPLE].decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw[:_SAMPLE].decode("latin-1")
    lines = text.splitlines()
    if truncated and lines:
        lines = lines[:-1]  # a partial last line
    return [ln for ln in lines if ln.strip() and not ln.lstrip().startswith(("#", "%"))]


def _split(line: str, d: str) -> list[str]:
    if d == " ":  # runs of blanks (tabs too) delimit; quoted names may hold blanks
        fields = next(csv.reader([line.replace("\t", " ").strip()], delimiter=" ",
                                 skipinitialspace=True))
        return [f.strip() for f in fields if f.strip()]
    return [f.strip() for f in next(csv.reader([line], delimiter=d))]


def _numeric(field: str, dec: str) -> bool:
    return field.lower() in _SPECIAL or bool(_NUM[dec].match(field))


def _reading(lines: list[str], d: str, dec: str, header: bool | None
             ) -> tuple[int, int, list[str]] | str:
    """``(header lines, columns, first-line fields)`` of a valid reading, else why not."""
    rows = [_split(ln, d) for ln in lines]
    n = len(rows[0])
    bad = next((i for i, r in enumerate(rows) if len(r) != n), None)
    if bad is not None:
        return (f"line {bad + 1} has {len(rows[bad])} fields, line 1 has {n}")
    if header is None:
        skip = 0
        while skip < min(2, len(rows) - 1) and not all(_numeric(f, dec) for f in rows[skip]):
            skip += 1
    else:
        skip = int(header) + (1 if header and len(rows) > 2 and not all(
            _numeric(f, dec) for f in rows[1]) else 0)
    for i, r in enumerate(rows[skip:], start=skip):
        if not all(_numeric(f, dec) for f in r):
            return f"line {i + 1} holds text in a data field: {lines[i][:60]!r}"
    return skip, n, rows[0]


def detect(lines: list[str], src: str, delimiter: str | None = None, decimal: str | None = None,
           header: bool | None = None) -> tuple[str, str, int]:
    """``(delimiter, decimal, header lines)`` of a table (module docstring)."""
    if not lines:
        raise InputError(f"{src}: the file holds no data lines")
    try:
        sniffed = csv.Sniffer().sniff("\n".join(lines[:50]), delimiters="".join(_CANDIDATES))
        first = (sniffed.delimiter,)
    except csv.Error:
        first = ()
    delims = (delimiter,) if delimiter else tuple(dict.fromkeys(first + _CANDIDATES))
    valid: dict[tuple[str, str], tuple[int, int, list[str]]] = {}
    why: dict[str, str] = {}
    for d in delims:
        for dec in ((decimal,) if decimal else ((".",) if d == "," else (".", ","))):
            r = _reading(lines, d, dec, header)
            if isinstance(r, str):
                why.setdefault(d, r)
            else:
                valid[(d, dec)] = r
    tables = {}
    for (d, dec), (skip, n, names) in valid.items():
        tables.setdefault((n, skip), (d, dec, names))
    if not valid:
        detail = "; ".join(f"{_NAMES.get(d, repr(d))}: {w}" for d, w in why.items())
        raise InputError(f"{src}: no consistent reading of the table (mixed delimiters or text "
                         f"in data lines? {detail}); give the delimiter and decimal mark "
                         "([measurement] delimiter/decimal) or fix the file")
    if len(tables) > 1:
        options = "; ".join(
            f"{_NAMES.get(d, repr(d))} delimiter, decimal '{dec}': {n} column(s) "
            f"{', '.join(names) if skip else '(no header)'}"
            for (n, skip), (d, dec, names) in tables.items())
        raise InputError(f"{src}: ambiguous table, it reads as {options}; give the delimiter and "
                         "decimal mark ([measurement] delimiter = …, decimal = …)")
    (d, dec), (skip, _, _) = next(iter(valid.items()))
    return d, dec, skip


def read_table(p: Path, delimiter: str | None = None, decimal: str | None = None,
               header: bool | None = None, time_channel: str | None = None) -> RawRecord:
    """Read a delimited text table (module docstring) into named channels."""
    import pandas as pd

    src = str(p)
    lines = _lines(p)
    d, dec, skip = detect(lines, src, delimiter, decimal, header)
    head = [_split(ln, d) for ln in lines[:skip]]
    df = pd.read_csv(p, sep=r"\s+" if d == " " else d, decimal=dec, header=None,
                     skiprows=_skip_rows(p, skip), comment=None, skipinitialspace=True,
                     engine="c", dtype=float, na_values=[""], keep_default_na=True)
    ncol = df.shape[1]
    if head:
        names_units = [split_unit(f) for f in head[0]]
        names = [n or str(i) for i, (n, _) in enumerate(names_units)]
        units = [u for _, u in names_units]
        if len(head) > 1:
            units = [u or v for u, v in zip(units, head[1], strict=False)]
    else:
        names, units = [str(i) for i in range(ncol)], [""] * ncol
    if len(set(names)) != len(names):
        raise InputError(f"{src}: duplicate column names {names}")
    notes = [f"{_NAMES.get(d, d)}-delimited, decimal '{dec}', "
             + (f"header {names}" if head else f"no header ({ncol} columns named 0…{ncol - 1})")]
    tcol = None
    if time_channel is not None:
        if time_channel not in names:
            raise InputError(f"{src}: time column '{time_channel}' does not exist; the file has "
                             f"columns {', '.join(names)}")
        tcol = time_channel
    else:
        tcol = next((n for n in names if is_time_name(n)), None)
        if tcol is None and ncol > 1 and is_uniform_time(df.iloc[:, 0].to_numpy()):
            tcol = names[0]
            notes.append(f"column '{tcol}' increases in uniform steps: taken as the time [s]")
    fs = None
    if tcol is not None:
        ti = names.index(tcol)
        t = df.iloc[:, ti].to_numpy()
        scale = _time_scale(units[ti], src, tcol)
        fs = uniform_rate(t * scale, f"{src}: time column '{tcol}'", rel=0.1)
        t0 = float(t[0] * scale)
    channels = {}
    for i, n in enumerate(names):
        if n == tcol:
            continue
        channels[n] = RawChannel(n, df.iloc[:, i].to_numpy(dtype=float), fs, units[i],
                                 t0 if tcol is not None else 0.0,
                                 attrs={"header": head[0][i]} if head else {})
    if not channels:
        raise InputError(f"{src}: no data column besides the time column '{tcol}'")
    return RawRecord(p, channels, tcol, None, notes, "table")


def _skip_rows(p: Path, skip: int) -> list[int]:
    """Line numbers (0-based) of comment lines and the ``skip`` header lines."""
    out, seen = [], 0
    with p.open("rb") as fh:
        for i, raw in enumerate(fh):
            s = raw.strip()
            if not s or s.startswith((b"#", b"%")):
                out.append(i)
                continue
            if seen < skip:
                out.append(i)
                seen += 1
                continue
            break  # comments and headers come before the data
    return out


def _time_scale(unit: str, src: str, col: str) -> float:
    if not unit:
        return 1.0
    from geardyn.config.units import to_unit

    try:
        return to_unit(f"1 {unit}", "s", "a time")
    except ValueError as exc:
        raise InputError(f"{src}: time column '{col}': unit {unit!r}: {exc}") from None


def first_column(p: Path) -> np.ndarray:
    """The first column of a table (header detected, never mistaken for data): pulse times."""
    import pandas as pd

    lines = _lines(p)
    d, dec, skip = detect(lines, str(p))
    df = pd.read_csv(p, sep=r"\s+" if d == " " else d, decimal=dec, header=None,
                     skiprows=_skip_rows(p, skip), engine="c", dtype=float, usecols=[0])
    return df.iloc[:, 0].to_numpy(dtype=float)
