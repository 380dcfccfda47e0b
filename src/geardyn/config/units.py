"""Numbers with units in configs: ``"3 mm"``, ``"1500 rpm"``, ``"20 deg"`` next to plain SI numbers.

Every numeric config field carries its unit in its name (``normal_module_m``,
``input_speeds_rpm``, ``dt_s``…; module docstring of :mod:`geardyn.config.gears`). Before
pydantic validation, :func:`convert_units` walks the parsed TOML and converts every string value
of such a field with pint to the field's unit; a wrong dimension is an error naming the field
(``planetary_dynamics.stages[0].carrier_radius_m: '3 rpm' is not a length``). The same pass
refuses implausible magnitudes (a speed over 1e6 rpm, a length over 100 m…) with the field named:
they are almost always a unit slip (mm typed in an m field).

Unit strings are parsed by a grammar (:func:`parse_quantity`) before pint sees them, never
evaluated: a decimal number and a unit expression, bounded in length and powers; the
expression's dimension (and power of the radian, which pint treats as dimensionless) must be
the field's; dimensionless units (ppm, percent) only in dimensionless fields
(:func:`dimensionless_field`).

Rotational speeds and frequencies: pint treats the radian as dimensionless, so ``"25 Hz"`` →
rpm would be read as 25 rad/s. Here a speed or frequency written without an angle unit (Hz,
1/s, 1/min) counts cycles (25 Hz = 1500 rpm); with one (rad/s, deg/s, rpm) it is converted
through rad/s.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from functools import lru_cache
from tokenize import TokenError
from typing import Any, NamedTuple


class Suffix(NamedTuple):
    """A field-name suffix: the pint unit of the field, its dimension in words, the largest
    plausible magnitude (SI, in the field's unit) and the smallest plausible non-zero one."""

    unit: str
    what: str
    limit: float
    floor: float = 0.0


#: Field-name suffix → unit. Longest suffixes first (``_n_per_m`` before ``_m``).
SUFFIXES: dict[str, Suffix] = {
    "_nms_per_rad": Suffix("N*m*s/rad", "a rotational damping (N·m·s/rad)", 1e12),
    "_nm_per_rad": Suffix("N*m/rad", "a torsional stiffness (N·m/rad)", 1e14),
    "_ns_per_m": Suffix("N*s/m", "a damping (N·s/m)", 1e12),
    "_n_per_m": Suffix("N/m", "a stiffness (N/m)", 1e14),
    "_kg_m3": Suffix("kg/m**3", "a density (kg/m³)", 1e5),
    "_kg_m": Suffix("kg*m", "an unbalance m·e (kg·m)", 1e4),
    # floors: a watch wheel (~1 mm, ~1 mg) has ~1e-13 kg·m²; 1e-15 kg·m² and 1e-9 kg (1 µg)
    # leave a factor of 100-1000 below the smallest gears made
    "_kgm2": Suffix("kg*m**2", "a moment of inertia (kg·m²)", 1e8, 1e-15),
    "_rpm": Suffix("rpm", "a rotational speed", 1e6),
    "_deg": Suffix("deg", "an angle", 3600.0),
    "_rad": Suffix("rad", "an angle", 100.0),
    "_hz": Suffix("Hz", "a frequency", 1e9),
    "_kg": Suffix("kg", "a mass", 1e7, 1e-9),
    "_nm": Suffix("N*m", "a torque", 1e9),
    "_pa": Suffix("Pa", "a pressure or modulus", 1e13),
    "_m": Suffix("m", "a length", 100.0),
    "_s": Suffix("s", "a time", 1e7),
    "_w": Suffix("W", "a power", 1e10),
    "_n": Suffix("N", "a force", 1e9),
}

#: Fields whose values are ``[[t_s, value], …]`` pairs: the first entry is a time.
PAIR_FIELDS = {"profile", "profile_rpm"}


def field_suffix(name: str) -> tuple[str, Suffix] | None:
    """The unit suffix of a field name (``carrier_radius_m`` → ``_m``), or None."""
    for suffix, info in SUFFIXES.items():
        if name.endswith(suffix) and len(name) > len(suffix):
            return suffix, info
    return None


def dimensionless_field(name: str) -> bool:
    """A field holding a dimensionless number (``damping_ratio``, ``amplitude``…)."""
    return name in DIMENSIONLESS_NAMES or (
        name.endswith(DIMENSIONLESS_ENDINGS) and name not in DIMENSIONLESS_ENDINGS)


@lru_cache(maxsize=1)
def registry() -> Any:
    """The pint unit registry (created on first use: pint takes ~0.2 s to load)."""
    import pint

    return pint.UnitRegistry()


#: Longest unit string accepted (characters): a number and a unit expression fit easily.
MAX_TEXT = 80
#: Largest integer power of one unit (m**3 for a density, s**-2…).
MAX_POWER = 4

_NUM = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d{1,4})?"
_NAME = r"(?:[^\W\d]|[°%])(?:[^\W\d]|_)*"
_TERM = _NAME + r"(?:\s*(?:\*\*|\^)\s*[+-]?\d{1,2})?"
_OP = r"(?:\s*[*/·⋅]\s*|\s+)"
_UNIT = rf"(?:1\s*/\s*)?{_TERM}(?:{_OP}{_TERM})*"
_GRAMMAR = re.compile(rf"\s*(?P<num>{_NUM})\s*(?P<unit>{_UNIT})?\s*")
_POWERS = re.compile(r"(?:\*\*|\^)\s*[+-]?(\d+)")


#: Fields without a unit suffix that hold a dimensionless number: a unit string there may use
#: dimensionless units (``"5 percent"``, ``"200 ppm"``); nowhere else.
DIMENSIONLESS_ENDINGS = ("_ratio", "_probability", "_fraction", "_confidence", "_coefficient")
DIMENSIONLESS_NAMES = frozenset({"amplitude", "modal_damping", "sigma_floor"})
DIMENSIONLESS = Suffix("dimensionless", "a dimensionless number", math.inf)


def _syntax_problem(text: str) -> str:
    """Why ``text`` does not follow the grammar NUMBER [UNIT]: the rule broken, in words."""
    if re.search(r"(?:\*\*|\^)\s*[+-]?[\d.]+\s*(?:\*\*|\^)", text):
        return "powers of powers are not allowed"
    if re.search(r"/\s*[+-]?0*\.?0+(?![\d.eE])", text):
        return "division by zero"
    if re.search(r"(?:\*\*|\^)\s*[+-]?\d*\.", text):
        return "a power must be a whole number"
    return ("expected a number followed by a unit, e.g. \"3 mm\", \"1500 rpm\", "
            "\"2.5 kg*m**2\" (products with * or a space, quotients with /, whole powers "
            f"with ** up to {MAX_POWER})")


def parse_quantity(text: str) -> tuple[float, str | None]:
    """``text`` read by the grammar NUMBER [UNIT] → (number, unit expression or None).

    The text is parsed, never evaluated: at most :data:`MAX_TEXT` characters, a decimal number
    (no arithmetic), then unit names joined by ``*``, ``/``, ``·`` or spaces, each with at most
    one whole power of magnitude ≤ :data:`MAX_POWER` (``m**2``; no ``m**2**3``), no numbers
    other than a leading ``1/`` (so no division by zero). ValueError naming the rule."""
    if len(text) > MAX_TEXT:
        raise ValueError(f"{text[:24]!r}… ({len(text)} characters) is longer than "
                         f"{MAX_TEXT} characters: not a number with a unit")
    m = _GRAMMAR.fullmatch(text)
    if m is None:
        raise ValueError(f"{text!r} is not a number with a unit ({_syntax_problem(text)})")
    for power in _POWERS.findall(m.group("unit") or ""):
        if int(power) > MAX_POWER:
            raise ValueError(f"{text!r} is not a number with a unit (power {power} is above "
                             f"{MAX_POWER})")
    value = float(m.group("num"))
    if not math.isfinite(value):
        raise ValueError(f"{text!r} is not a finite number")
    unit = m.group("unit")
    if unit is None:
        return value, None
    return value, unit.replace("^", "**").replace("·", "*").replace("⋅", "*")


def _signature(units: Any) -> tuple[Any, int, list[str]]:
    """(pint dimensionality, power of the radian, names of pure-scale units such as ppm)."""
    ureg = registry()
    rad, scales = 0, []
    for name, power in units._units.items():
        root = ureg.Quantity(1.0, name).to_root_units()
        r = dict(root._units)
        rad += int(round(r.pop("radian", 0) * power))
        if not r and not dict(root._units):
            scales.append(name)
    return units.dimensionality, rad, scales


def to_unit(text: str, unit: str, what: str) -> float:
    """``text`` (e.g. ``"3 mm"``) as a number in ``unit``; ValueError naming the rule.

    A string without a unit is read in the field's unit. Speeds (rpm) and frequencies (Hz)
    count cycles unless the text names an angle (module docstring). Angles need an angle unit;
    dimensionless units (ppm, percent) are accepted only for a dimensionless field
    (``unit == "dimensionless"``)."""
    import pint

    number, expr = parse_quantity(text.strip())
    if expr is None:
        return number
    ureg = registry()
    try:
        units = ureg.parse_units(expr)
        dim, rad, scales = _signature(units)
        q = ureg.Quantity(number, units)
    except (pint.errors.PintError, SyntaxError, ValueError, TypeError, AttributeError,
            KeyError, TokenError, ZeroDivisionError, OverflowError) as exc:
        raise ValueError(f"{text!r} is not a number with a unit ({exc})") from None
    if unit == "dimensionless":
        if dim or rad:
            raise ValueError(f"{text!r} is not {what} (expected a dimensionless unit such as "
                             "percent or ppm, or a plain number)")
        value = float(q.to("dimensionless").magnitude)
    elif scales:
        raise ValueError(f"{text!r} is not {what}: {', '.join(scales)} is dimensionless "
                         f"(expected a unit convertible to {unit})")
    elif unit in ("rpm", "Hz"):
        if rad not in (0, 1):
            raise ValueError(f"{text!r} is not {what} (expected rpm, Hz, rad/s…)")
        value = _rate(q, unit, text, what, angular=rad == 1)
    else:
        want_dim, want_rad, _ = _signature(ureg.parse_units(unit))
        angle = unit in ("deg", "rad")
        if dim != want_dim or rad not in ((want_rad,) if angle else (want_rad, 0)):
            raise ValueError(f"{text!r} is not {what} (expected a unit convertible to "
                             f"{unit})")
        try:
            value = float(q.to(unit).magnitude)
        except pint.errors.PintError:
            raise ValueError(f"{text!r} is not {what} (expected a unit convertible to "
                             f"{unit})") from None
    if not math.isfinite(value):
        raise ValueError(f"{text!r} is not a finite number")
    return value


def _rate(q: Any, unit: str, text: str, what: str, *, angular: bool) -> float:
    import pint

    try:
        rev_s = float(q.to("revolution/s" if angular else "1/s").magnitude)
    except pint.errors.DimensionalityError:
        raise ValueError(f"{text!r} is not {what} (expected rpm, Hz, rad/s…)") from None
    return rev_s * 60.0 if unit == "rpm" else rev_s


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
    elif number and math.isfinite(value) and 0 < abs(value) < unit.floor:
        problems.append(f"{path}: {value:g} {unit.unit} is implausible for {unit.what} "
                        f"(smallest {unit.floor:g} {unit.unit}: below the smallest gears made; "
                        "a unit slip?)")
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
            elif dimensionless_field(str(key)) and isinstance(value, str):
                out[key] = _convert_value(value, DIMENSIONLESS, sub, problems)
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
                    elif dimensionless_field(name) and isinstance(prop, dict):
                        _allow_strings(prop, DIMENSIONLESS._replace(unit="percent"))
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
