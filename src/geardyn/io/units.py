"""Units and sensitivity of a channel, through pint (:mod:`geardyn.config.units` registry).

A file value ``v`` [file units] (or, for audio, a fraction of digital full scale, ``v`` ×
``full_scale``) divided by the transducer ``sensitivity`` is the physical quantity; ``g`` in a
sensitivity is standard gravity (9.80665 m/s², ``"100 mV/g"``)."""

from __future__ import annotations

from geardyn.config.measurement import parse_quantity
from geardyn.errors import InputError


def scale_factor(file_units: str, sensitivity: str | None, full_scale: str | None,
                 target: str | None, src: str) -> tuple[float, str]:
    """``(factor, units)``: file values × factor are in ``units`` (``target``, else the SI
    base units of the result when a sensitivity is given, else the file's units)."""
    q = (parse_quantity(full_scale, "a full-scale quantity") if full_scale
         else parse_quantity(f"1 {file_units}" if file_units else "1", "a unit"))
    if sensitivity:
        q = q / parse_quantity(sensitivity, "a sensitivity")
    if target is None:
        if sensitivity:
            q = q.to_base_units()
        units = "" if q.unitless else f"{q.units:~}".replace(" ", "").replace("**", "^")
        return float(q.magnitude), units
    try:
        return float(q.to(parse_quantity(f"1 {target}", "a unit").units).magnitude), target
    except Exception:  # noqa: BLE001 - pint DimensionalityError
        how = f"values in {q.units:~}" if not q.unitless else "dimensionless values"
        raise InputError(f"{src}: {how} (file units {file_units or 'none'}"
                         + (f", sensitivity {sensitivity}" if sensitivity else "")
                         + (f", full scale {full_scale}" if full_scale else "")
                         + f") cannot be expressed in {target}; check units, file_units and "
                         "sensitivity") from None
