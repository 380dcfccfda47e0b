"""Reading TOML configs and turning validation failures into messages that name the item."""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pydantic import Field, ValidationError, model_validator

from geardyn.config.diagnosis import DiagnosisSpec, check_diagnosis
from geardyn.config.dynamics import Dynamics, check_dynamics
from geardyn.config.gears import GearGeometryConfig, check_gear_geometry
from geardyn.config.measurement import MeasurementSpec, check_measurement
from geardyn.config.mechanism import Mechanism
from geardyn.config.planetary import PlanetaryDynamics, check_planetary_dynamics
from geardyn.config.sensors import SensorSpec, check_sensors
from geardyn.config.transmission import TransmissionConfig, check_transmission
from geardyn.config.units import convert_units
from geardyn.errors import ConfigError


class GeardynConfig(Mechanism):
    """A whole geardyn config file: the mechanism (top level) plus optional analysis sections.

    Analysis modules add their sections here as optional fields (e.g. gear geometry, model and
    simulation settings); a file holding only a mechanism is a valid config.
    """

    @model_validator(mode="before")
    @classmethod
    def _units(cls, data: Any) -> Any:
        """Numbers written with a unit (``"3 mm"``) → the field's unit; wrong dimensions and
        implausible magnitudes refused naming the field (:mod:`geardyn.config.units`)."""
        if not isinstance(data, Mapping):
            return data
        problems: list[str] = []
        data = convert_units(data, problems=problems)
        if problems:
            raise ValueError("\n".join(problems))
        return data

    gear_geometry: list[GearGeometryConfig] = Field(
        default_factory=list,
        description="gear geometry attached to named gear pairs (see geardyn.config.gears)",
    )

    @model_validator(mode="after")
    def _check_gear_geometry(self) -> GeardynConfig:
        problems = check_gear_geometry(self)
        if problems:
            raise ValueError("\n".join(problems))
        return self

    planetary_dynamics: PlanetaryDynamics | None = Field(
        None, description="lumped planetary model and simulation (geardyn.config.planetary)"
    )

    @model_validator(mode="after")
    def _check_planetary_dynamics(self) -> GeardynConfig:
        problems = check_planetary_dynamics(self)
        if problems:
            raise ValueError("\n".join(problems))
        return self

    transmission: TransmissionConfig | None = Field(
        None, description="finite-element transmission model (see geardyn.config.transmission)"
    )

    @model_validator(mode="after")
    def _check_transmission(self) -> GeardynConfig:
        problems = check_transmission(self)
        if problems:
            raise ValueError("\n".join(problems))
        return self


    sensors: list[SensorSpec] = Field(
        default_factory=list, description="simulated sensors (see geardyn.config.sensors)"
    )

    @model_validator(mode="after")
    def _check_sensors(self) -> GeardynConfig:
        problems = check_sensors(self)
        if problems:
            raise ValueError("\n".join(problems))
        return self

    diagnosis: DiagnosisSpec | None = Field(
        None, description="baseline, thresholds and verdict (see geardyn.config.diagnosis)"
    )

    @model_validator(mode="after")
    def _check_diagnosis(self) -> GeardynConfig:
        problems = check_diagnosis(self)
        if problems:
            raise ValueError("\n".join(problems))
        return self

    measurement: MeasurementSpec | None = Field(
        None, description="channel mapping of measured records (see geardyn.config.measurement)"
    )

    @model_validator(mode="after")
    def _check_measurement(self) -> GeardynConfig:
        problems = check_measurement(self)
        if problems:
            raise ValueError("\n".join(problems))
        return self

    dynamics: Dynamics | None = Field(
        None, description="general torsional model of the mechanism (see geardyn.config.dynamics)"
    )

    @model_validator(mode="after")
    def _check_dynamics(self) -> GeardynConfig:
        problems = check_dynamics(self)
        if problems:
            raise ValueError("\n".join(problems))
        return self

    @model_validator(mode="after")
    def _check_resources(self) -> GeardynConfig:
        """The config's own runs fit the resource limits (time steps, samples of the result
        and of every sensor channel; :mod:`geardyn.resources`), checked before any run."""
        from geardyn.resources import run_problems

        problems = run_problems(self)
        if problems:
            raise ValueError("\n".join(problems))
        return self


def _loc_to_path(loc: tuple[Any, ...], data: Any) -> str:
    parts: list[str] = []
    node = data
    for item in loc:
        if isinstance(item, int):
            label = f"[{item}]"
            try:
                node = node[item]
                if isinstance(node, Mapping) and isinstance(node.get("name"), str):
                    label += f" '{node['name']}'"
            except (IndexError, KeyError, TypeError):
                node = None
            parts.append(label)
        else:
            # pydantic adds function/union tags to some locations; keep only field names
            if isinstance(node, Mapping) and item in node:
                node = node[item]
                parts.append(f".{item}" if parts else str(item))
            elif "[" in str(item) or str(item).startswith("function-"):
                continue
            else:
                node = None
                parts.append(f".{item}" if parts else str(item))
    return "".join(parts)


def format_validation_error(exc: ValidationError, data: Any) -> list[str]:
    """One message per broken rule, each prefixed with the path of the item (e.g.
    ``gear_pairs[1] 'drive'.a.teeth: ...``)."""
    msgs: list[str] = []
    for err in exc.errors():
        path = _loc_to_path(tuple(err.get("loc", ())), data)
        msg = str(err.get("msg", ""))
        for prefix in ("Value error, ", "Assertion failed, "):
            if msg.startswith(prefix):
                msg = msg[len(prefix) :]
        if err.get("type") == "extra_forbidden":
            msg = "unknown field (check the spelling; see the docs for the allowed fields)"
        elif err.get("type") == "missing":
            msg = "required field is missing"
        elif "input" in err and err.get("type") not in ("value_error", "assertion_error"):
            msg = f"{msg} (got {err['input']!r})"
        for line in msg.split("\n"):
            msgs.append(f"{path}: {line}" if path else line)
    return msgs


#: Deepest nesting of arrays and tables accepted in a TOML file (a geardyn config or sweep
#: spec nests a handful of levels: [[planetary_dynamics.simulation.speed_controls]] profile
#: pairs are 5 deep).
MAX_DEPTH = 32


def nesting_depth(data: Any) -> int:
    """Deepest nesting of lists and mappings in ``data`` (iterative: no recursion limit)."""
    deepest, todo = 0, [(data, 0)]
    while todo:
        node, depth = todo.pop()
        if isinstance(node, Mapping | list):
            deepest = max(deepest, depth + 1)
            if deepest > MAX_DEPTH:
                return deepest
            todo.extend((v, depth + 1) for v in (node.values() if isinstance(node, Mapping)
                                                  else node))
    return deepest


def check_path_length(path: Path, what: str) -> None:
    """ConfigError naming ``what`` when a component of ``path`` is longer than 255 bytes or
    the path longer than 4096 (Linux NAME_MAX / PATH_MAX: the system call would fail)."""
    text = str(path)
    longest = max((len(c.encode("utf-8", "surrogateescape")) for c in text.split("/")),
                  default=0)
    if longest > 255 or len(text.encode("utf-8", "surrogateescape")) > 4096:
        raise ConfigError(f"{what}: the file name ({longest} characters) or the path "
                          f"({len(text)}) is longer than the file system accepts (255 per "
                          "name, 4096 per path)")


def read_toml(path: Path, what: str) -> dict[str, Any]:
    """Parse the TOML file ``path``; ConfigError naming the file and the rule for text that is
    not UTF-8, not TOML, nested deeper than :data:`MAX_DEPTH`, or unreadable."""
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"not valid TOML: {exc}", source=str(path)) from None
    except UnicodeDecodeError as exc:
        raise ConfigError(f"not valid TOML: not UTF-8 text ({exc.reason} at byte "
                          f"{exc.start})", source=str(path)) from None
    except RecursionError:
        raise ConfigError(f"not valid TOML for a {what}: arrays or tables nested too deeply "
                          f"(limit {MAX_DEPTH} levels)", source=str(path)) from None
    except OSError as exc:
        raise ConfigError(f"cannot read the {what}: {exc.strerror or exc}",
                          source=str(path)) from None
    depth = nesting_depth(data)
    if depth > MAX_DEPTH:
        raise ConfigError(f"arrays or tables nested too deeply for a {what} (more than "
                          f"{MAX_DEPTH} levels)", source=str(path))
    return data


def parse_config(data: Mapping[str, Any], source: str | None = None) -> GeardynConfig:
    """Validate a config held in a mapping (e.g. parsed TOML).

    Numbers may be written as strings with a unit (``"3 mm"``): a first pass
    (:meth:`GeardynConfig._units`) converts them to the unit in the field's name and refuses
    wrong dimensions and implausible magnitudes (:mod:`geardyn.config.units`), naming the
    field."""
    try:
        return GeardynConfig.model_validate(dict(data))
    except ValidationError as exc:
        raise ConfigError(format_validation_error(exc, data), source=source) from None


def load_config(path: str | Path) -> GeardynConfig:
    """Read and validate a TOML config file."""
    p = Path(path)
    check_path_length(p, "config file")
    if p.is_dir():
        raise ConfigError(f"config file '{p}' is a directory, expected a TOML file")
    if not p.is_file():
        raise ConfigError(f"config file '{p}' does not exist")
    data = read_toml(p, "config file")
    return parse_config(data, source=str(p))
