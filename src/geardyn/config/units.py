"""Numbers with units in configs: ``"3 mm"``, ``"1500 rpm"``, ``"20 deg"`` next to plain SI numbers.

Every numeric config field carries its unit in its name (``normal_module_m``,
``input_speeds_rpm``, ``dt_s``…; module docstring of :mod:`geardyn.config.gears`). Before
pydantic validation, :func:`convert_units` walks the parsed TOML and converts every string value
of such a field with pint to the field's unit; a wrong dimension is an error naming the field
(``planetary_dynamics.stages[0].carrier_radius_m: '3 rpm' is not a length``). The same pass
refuses implausible magnitudes (a speed over 1e6 rpm, a length over 100 m…) with the field named:
they are almost always a unit slip (mm typed in an m field).

Rotational speeds and frequencies: pint treats the radian as dimensionless, so ``"25 Hz"`` →
rpm would be read as 25 rad/s. Here a speed or frequency written without an angle unit (Hz,
1/s, 1/min) counts cycles (25 Hz = 1500 rpm); with one (rad/s, deg/s, rpm) it is converted
through rad/s.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from functools import lru_cache
from typing import Any, NamedTuple


class Suffix(NamedTuple):
    """A field-name suffix: the pint unit of the field, its dimension in words, the largest
    plausible magnitude (SI, in the field's unit)."""

    unit: str
    what: str
    limit: float


#: Field-name suffix → unit. Longest suffixes first (``_n_per_m`` before ``_m``).
SUFFIXES: dict[str, Suffix] = {
    "_nms_per_rad": Suffix("N*m*s/rad", "a rotational damping (N·m·s/rad)", 1e12),
    "_nm_per_rad": Suffix("N*m/rad", "a torsional stiffness (N·m/rad)", 1e14),
    "_ns_per_m": Suffix("N*s/m", "a damping (N·s/m)", 1e12),
    "_n_per_m": Suffix("N/m", "a stiffness (N/m)", 1e14),
    "_kg_m3": Suffix("kg/m**3", "a density (kg/m³)", 1e5),
    "_kg_m": Suffix("kg*m", "an unbalance m·e (kg·m)", 1e4),
    "_kgm2": Suffix("kg*m**2", "a moment of inertia (kg·m²)", 1e8),
    "_rpm": Suffix("rpm", "a rotational speed", 1e6),
    "_deg": Suffix("deg", "an angle", 3600.0),
    "_rad": Suffix("rad", "an angle", 100.0),
    "_hz": Suffix("Hz", "a frequency", 1e9),
    "_kg": Suffix("kg", "a mass", 1e7),
    "_nm": Suffix("N*m", "a torque", 1e9),
    "_pa": Suffix("Pa", "a pressure or modulus", 1e13),
    "_m": Suffix("m", "a length", 100.0),
    "_s": Suffix("s", "a time", 1e7),
    "_w": Suffix("W", "a power", 1e10),
    "_n": Suffix("N", "a force", 1e9),
}

#: Fields whose values are ``[[t_s, value], …]`` pairs: the first entry is a time.
PAIR_FIELDS = {"profile", "profile_rpm"}

_ANGLE_UNITS = ("radian", "degree", "revolution", "turn", "arcminute", "arcsecond", "gradian")


def field_suffix(name: str) -> tuple[str, Suffix] | None:
    """The unit suffix of a field name (``carrier_radius_m`` → ``_m``), or None."""
    for suffix, info in SUFFIXES.items():
        if name.endswith(suffix) and len(name) > len(suffix):
            return suffix, info
    return None


@lru_cache(maxsize=1)
def registry() -> Any:
    """The pint unit registry (created on first use: pint takes ~0.2 s to load)."""
    import pint

    return pint.UnitRegistry()


def to_unit(text: str, unit: str, what: str) -> float:
    """``text`` (e.g. ``"3 mm"``) as a number in ``unit``; ValueError naming the rule.

    A string without a unit is read in the field's unit. Speeds (rpm) and frequencies (Hz)
    count cycles unless the text names an angle (module docstring)."""
    import pint

    ureg = registry()
    try:
        q = ureg.Quantity(text.strip())
    except (pint.errors.PintError, SyntaxError, ValueError, TypeError, AttributeError,
            KeyError, TokenError) as exc:
        raise ValueError(f"{text!r} is not a number with a unit ({exc})") from None
    if not isinstance(q, ureg.Quantity):  # a bare number parses to int/float
        value = float(q)
    elif q.unitless:
        value = float(q.magnitude)
    elif unit in ("rpm", "Hz"):
        value = _rate(q, unit, text, what)
    else:
        try:
            value = float(q.to(unit).magnitude)
        except pint.errors.DimensionalityError:
            raise ValueError(f"{text!r} is not {what} (expected a unit convertible to "
                             f"{unit})") from None
    if not math.isfinite(value):
        raise ValueError(f"{text!r} is not a finite number")
    return value


def _rate(q: Any, unit: str, text: str, what: str) -> float:
    import pint

    names = " ".join(str(u) for u in q.unit_items()) if hasattr(q, "unit_items") else str(q.units)
    angular = any(a in names for a in _ANGLE_UNITS)
    try:
        rev_s = float(q.to("revolution/s" if angular else "1/s").magnitude)
    except pint.errors.DimensionalityError:
        raise ValueError(f"{text!r} is not {what} (expected rpm, Hz, rad/s…)") from None
    return rev_s * 60.0 if unit == "rpm" else rev_s


try:  # tokenize errors from pint's parser
    from tokenize import TokenError
except ImportError:  # pragma: no cover
    TokenError = SyntaxError  # type: ignore[misc,assignment]


def _convert_value(value: Any, unit: Suffix, path: str, problems: list[str]) -> Any:
    if isinstance(value, bool):
        problems.append(f"{path}: expected a number ({unit.what}), got {str(value).lower()}")
        return value
    if isinstance(value, str):
        try:
            value = to_unit(value, unit.unit, unit.what)
        except ValueError as exc:
            problems.append(f"{path}: {exc}")
            return value
    number = isinstance(value, int | float) and not isinstance(value, bool)
    if number and math.isfinite(value) and abs(value) > unit.limit:
        problems.append(f"{path}: {value:g} {unit.unit} is implausible for {unit.what} "
                            f"(limit {unit.limit:g} {unit.unit}; a unit slip? numbers are SI "
                            "unless written with a unit, e.g. \"3 mm\")")
    return value


def _convert_field(value: Any, name: str, unit: Suffix, path: str,
                   problems: list[str]) -> Any:
    if isinstance(value, list):
        out = []
        for i, item in enumerate(value):
            if name in PAIR_FIELDS and isinstance(item, list) and len(item) == 2:
                out.append([_convert_value(item[0], SUFFIXES["_s"], f"{path}[{i}][0]", problems),
                            _convert_value(item[1], unit, f"{path}[{i}][1]", problems)])
            else:
                out.append(_convert_value(item, unit, f"{path}[{i}]", problems))
        return out
    if isinstance(value, Mapping):
        return {k: _convert_value(v, unit, f"{path}.{k}", problems) for k, v in value.items()}
    return _convert_value(value, unit, path, problems)


def _label(path: str, index: int, item: Any) -> str:
    label = f"{path}[{index}]"
    if isinstance(item, Mapping) and isinstance(item.get("name"), str):
        label += f" '{item['name']}'"
    return label


def convert_units(data: Any, path: str = "", problems: list[str] | None = None) -> Any:
    """A copy of ``data`` (parsed TOML) with every string value of a unit-suffixed field
    converted to the field's unit; appends one message per problem to ``problems``."""
    problems = [] if problems is None else problems
    if isinstance(data, Mapping):
        out: dict[str, Any] = {}
        for key, value in data.items():
            sub = f"{path}.{key}" if path else str(key)
            found = field_suffix(str(key))
            if str(key) in PAIR_FIELDS and isinstance(value, list):
                unit = found[1] if found else SUFFIXES["_nm"]  # torque profile [[t_s, N·m]]
                out[key] = _convert_field(value, str(key), unit, sub, problems)
            elif found is not None:
                out[key] = _convert_field(value, str(key), found[1], sub, problems)
            else:
                out[key] = convert_units(value, sub, problems)
        return out
    if isinstance(data, list):
        return [convert_units(item, _label(path, i, item), problems)
                for i, item in enumerate(data)]
    return data


def annotate_schema(schema: dict[str, Any]) -> dict[str, Any]:
    """Let every unit-suffixed number in a JSON Schema also be a string with a unit."""

    def visit(node: Any) -> None:
        if isinstance(node, dict):
            props = node.get("properties")
            if isinstance(props, dict):
                for name, prop in props.items():
                    found = field_suffix(name)
                    if found is not None and isinstance(prop, dict):
                        _allow_strings(prop, found[1])
            for value in node.values():
                visit(value)
        elif isinstance(node, list):
            for value in node:
                visit(value)

    visit(schema)
    return schema


def _allow_strings(prop: dict[str, Any], unit: Suffix) -> None:
    text = {"type": "string", "description": f"{unit.what} with a unit, e.g. \"1 {unit.unit}\""}
    if prop.get("type") in ("number", "integer"):
        number = {k: prop.pop(k) for k in list(prop)
                  if k in ("type", "exclusiveMinimum", "minimum", "maximum", "exclusiveMaximum")}
        prop["anyOf"] = [number, text]
    elif isinstance(prop.get("anyOf"), list) and any(
            isinstance(o, dict) and o.get("type") in ("number", "integer") for o in prop["anyOf"]):
        prop["anyOf"].append(text)
