"""Sweep specs (TOML): a base config, axes over dotted config paths, the outputs to keep.

A spec names a base config file and **axes**, each a dotted path into that config
(``planetary_dynamics.stages[0].faults[0].crack_fraction``, ``input_speeds_rpm.sun``,
``planetary_dynamics.simulation.support_damping["sun.x"]``) with its values given as a list,
a range or a random / Latin-hypercube draw. Axes sharing a ``group`` are zipped (equal lengths,
element by element); groups combine as a Cartesian product (``combine = "product"``, the first
group varying slowest) or are zipped too (``combine = "zip"``). Each combination is run
``replicates`` times, each case with its own seed :func:`case_seed`.

Everything is checked before anything runs (:func:`load_spec` / :func:`expand`): unknown or
misspelled fields, an axis path that does not exist in the base config, an empty axis, a value
of the wrong type, a number of cases above ``max_cases``, and every case's config validated
like a config file — each message names the axis (and the case).
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from geardyn.errors import ConfigError

#: Default ceiling on the number of cases (``[sweep].max_cases`` raises it explicitly).
MAX_CASES = 10_000


class _M(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


class RangeSpec(_M):
    """Evenly spaced values: ``num`` points from ``start`` to ``stop`` inclusive, or ``start``,
    ``start + step``, … up to ``stop`` inclusive."""

    start: float
    stop: float
    num: int | None = Field(None, ge=1)
    step: float | None = Field(None, gt=0)

    @model_validator(mode="after")
    def _one(self) -> RangeSpec:
        if (self.num is None) == (self.step is None):
            raise ValueError("give exactly one of num (number of points) or step")
        if self.stop < self.start:
            raise ValueError(f"stop {self.stop:g} is below start {self.start:g}")
        return self

    def count(self) -> float:
        """Number of values, computed without listing them (inf when it overflows)."""
        if self.num is not None:
            return float(self.num)
        span = (self.stop - self.start) / self.step * (1 + 1e-12)  # type: ignore[operator]
        return math.floor(span) + 1.0 if math.isfinite(span) else math.inf

    def values(self) -> list[float]:
        if self.num is not None:
            return [float(v) for v in np.linspace(self.start, self.stop, self.num)]
        n = int(self.count())
        return [float(self.start + i * self.step) for i in range(n)]  # type: ignore[operator]


class SampleSpec(_M):
    """``n`` random values in ``[low, high)``: independent uniform draws (``uniform``) or a
    Latin hypercube (``latin_hypercube``; axes of one group with this method are drawn jointly,
    one stratum per value and axis, McKay, Beckman & Conover 1979)."""

    low: float
    high: float
    n: int = Field(ge=1)
    method: Literal["uniform", "latin_hypercube"] = "uniform"

    @model_validator(mode="after")
    def _bounds(self) -> SampleSpec:
        if not self.high > self.low:
            raise ValueError(f"high {self.high:g} must exceed low {self.low:g}")
        return self


class AxisSpec(_M):
    """One axis of a sweep: a config path and its values (exactly one of ``values``,
    ``range``, ``sample``); ``labels`` name non-scalar values (or relabel scalar ones) in the
    store's coordinate; axes with the same ``group`` are zipped."""

    name: str = Field(min_length=1, pattern=r"^[A-Za-z_][A-Za-z0-9_]*$",
                      description="coordinate name in the data set")
    path: str = Field(min_length=1, description="dotted path into the base config")
    values: list[Any] | None = None
    range: RangeSpec | None = None
    sample: SampleSpec | None = None
    labels: list[str | float | int | bool] | None = None
    group: str | None = Field(None, description="axes of one group are zipped")
    units: str = Field("", description="units of the values (coordinate attribute)")

    @model_validator(mode="after")
    def _one_source(self) -> AxisSpec:
        given = [k for k in ("values", "range", "sample") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of values, range or sample"
                             + (f" (got {', '.join(given)})" if given else ""))
        if self.values is not None and not self.values:
            raise ValueError("values: the axis is empty; give at least one value")
        return self


class SweepSection(_M):
    """``[sweep]``: base config, seed, combination, replicates, size limit."""

    base: str = Field(description="base config file (relative to the spec file)")
    name: str = ""
    seed: int = Field(0, ge=0, description="sweep seed: case seeds = f(seed, case index)")
    combine: Literal["product", "zip"] = "product"
    replicates: int = Field(1, ge=1, description="runs of each combination (own seeds)")
    max_cases: int = Field(MAX_CASES, ge=1, description="refuse sweeps with more cases")


class RunSection(_M):
    """``[run]``: run-length overrides passed to :func:`geardyn.run.run_simulation`."""

    t_end_s: float | None = Field(None, gt=0, description="planetary model: duration (s)")
    revolutions: float | None = Field(None, gt=0, description="FE transmission: revolutions")


class ChannelOutput(_M):
    """Sensor channels kept: the last ``samples`` samples of each (after keeping every
    ``every``-th; time-sampled channels are low-pass filtered first), NaN-padded."""

    names: list[str] = Field(default_factory=list)
    every: int = Field(1, ge=1)
    samples: int = Field(8192, ge=1)


class StateOutput(_M):
    """Model states kept on a coarse time grid ``0, step_s, 2 step_s, …`` (linear
    interpolation of the result's ``time`` samples)."""

    variables: list[Literal["angle", "speed", "speed_rpm", "mesh_force"]] = Field(
        default_factory=list)
    step_s: float = Field(0.01, gt=0)


class IndicatorOutput(_M):
    """Condition indicators per component (geardyn.diagnosis.features) of one channel;
    ``None`` fields take the base config's ``[diagnosis]`` values."""

    enabled: bool = True
    channel: str | None = None
    skip_s: float | None = Field(None, ge=0)
    blocks: int | None = Field(None, ge=1, le=64)


class VerdictOutput(_M):
    """Detection verdicts against a healthy baseline made of the sweep's own cases:
    ``healthy`` selects them by axis value (``{fault_gear = "none"}``), ``match`` lists the
    axes a baseline case must share with the judged case (operating point). The per-test
    level is set as ``geardyn diagnose`` sets it: from ``false_alarm_probability`` by the
    Šidák correction over the tests of each case (Šidák 1967), unless ``threshold_k`` fixes
    the factor."""

    healthy: dict[str, str | float | int | bool]
    match: list[str] = Field(default_factory=list)
    false_alarm_probability: float = Field(
        0.01, gt=0, lt=1,
        description="probability that a healthy case is reported detected (machine level): "
        "per-test level α = 1 − (1 − P)^(1/m) over the m tests of the case (Šidák 1967)")
    threshold_k: float | None = Field(
        None, gt=0, description="fixed threshold factor (mean + k·σ); overrides "
        "false_alarm_probability (α = Φ(−k) per test)")
    sigma_floor: float | None = Field(None, ge=0, lt=1)
    localisation_confidence: float = Field(
        0.95, ge=0.5, lt=1,
        description="posterior probability a component needs to be named as the location")


class DiagnosisOutput(_M):
    """Each case judged as ``geardyn diagnose`` judges its config (:mod:`geardyn.sweep.
    diagnosis`): the case runs with its config's ``diagnosis.record_seed`` and is judged
    against the healthy baseline ensemble of its own config (``[diagnosis.ensemble]`` of the
    config with its faults removed), simulated once per healthy config and shared through a
    cache in the store."""

    record_machine: Literal["nominal", "fleet"] = Field(
        "nominal", description="nominal: the config as written (as geardyn diagnose); fleet: "
        "another machine of the baseline's fleet (the ensemble's perturbations, seeded by "
        "fleet_seed and the healthy config; its run seed mixes record_seed with the healthy "
        "config, so two configs' machines never share manufacturing-error or noise draws)")
    fleet_seed: int = Field(0, ge=0, description="seed of the fleet draws (record_machine = "
                            "'fleet')")


class OutputSpec(_M):
    """``[outputs]``: what each case stores."""

    channels: ChannelOutput = Field(default_factory=ChannelOutput)
    states: StateOutput = Field(default_factory=StateOutput)
    indicators: IndicatorOutput = Field(default_factory=IndicatorOutput)
    verdicts: VerdictOutput | None = None
    diagnosis: DiagnosisOutput | None = None


class SweepSpec(_M):
    """A whole sweep spec (TOML): ``[sweep]``, ``[run]``, ``[[axes]]``, ``[outputs]``."""

    sweep: SweepSection
    run: RunSection = Field(default_factory=RunSection)
    axes: list[AxisSpec] = Field(min_length=1)
    outputs: OutputSpec = Field(default_factory=OutputSpec)

    @model_validator(mode="after")
    def _names(self) -> SweepSpec:
        names = [a.name for a in self.axes]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"axis names must be distinct: {', '.join(dup)} repeated")
        reserved = {"case", "seed", "replicate", "status", "message"}
        bad = sorted(set(names) & reserved)
        if bad:
            raise ValueError(f"axis name(s) {', '.join(bad)} are reserved ({sorted(reserved)})")
        v = self.outputs.verdicts
        if v is not None:
            unknown = sorted((set(v.healthy) | set(v.match)) - set(names))
            if unknown:
                raise ValueError(f"outputs.verdicts: {', '.join(unknown)} is not an axis name "
                                 f"(axes: {', '.join(names)})")
            from geardyn.sweep.verdicts import VARIABLES

            clash = sorted(set(names) & set(VARIABLES))
            if clash:
                raise ValueError(f"axis name(s) {', '.join(clash)} are the names of verdict "
                                 "variables (outputs.verdicts); rename the axis")
        if self.outputs.diagnosis is not None and self.sweep.replicates != 1:
            raise ValueError(f"sweep.replicates = {self.sweep.replicates}: with "
                             "[outputs.diagnosis] each case is the record of geardyn diagnose, "
                             "run with its config's diagnosis.record_seed; replicates would "
                             "repeat it: vary that seed with an axis (path "
                             "'diagnosis.record_seed') instead")
        return self


# ---------------------------------------------------------------------------- paths
_TOKEN = re.compile(r"""\.?([A-Za-z_][A-Za-z0-9_]*)|\[(\d+)\]|\[\s*["']([^"']+)["']\s*\]""")


def parse_path(path: str) -> list[str | int]:
    """``'a.b[0].c["x.y"]'`` → ``['a', 'b', 0, 'c', 'x.y']``; ConfigError if malformed."""
    out: list[str | int] = []
    pos = 0
    while pos < len(path):
        m = _TOKEN.match(path, pos)
        if m is None or (pos == 0 and path.startswith(".")):
            raise ConfigError(f"path '{path}': cannot read it at character {pos + 1} "
                              "(expected name, .name, [index] or [\"key\"])")
        name, index, key = m.groups()
        out.append(name if name is not None else int(index) if index is not None else key)
        pos = m.end()
    if not out:
        raise ConfigError("path: empty")
    return out


def _walk(data: Any, parts: list[str | int], path: str) -> tuple[Any, str | int]:
    """Container holding the last element of ``parts`` (which must exist) and its key."""
    node = data
    done = ""
    for i, p in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(p, int):
            if not isinstance(node, list):
                raise KeyError(f"'{done}' is not a list, [{p}] does not apply")
            if not 0 <= p < len(node):
                raise KeyError(f"'{done}' has {len(node)} item(s), index [{p}] does not exist")
        else:
            if not isinstance(node, dict):
                raise KeyError(f"'{done or '(top)'}' is not a table, '{p}' does not apply")
            if p not in node:
                near = ", ".join(sorted(str(k) for k in node)[:12])
                where = f"'{done}'" if done else "the config's top level"
                raise KeyError(f"{where} has no field '{p}' (fields: {near})")
        if last:
            return node, p
        node = node[p]
        done += f"[{p}]" if isinstance(p, int) else (f".{p}" if done else str(p))
    raise KeyError(path)  # pragma: no cover - parts is never empty


def set_path(data: dict[str, Any], path: str, value: Any) -> None:
    """Set ``path`` (which must exist) in the nested dict/list ``data`` to ``value``."""
    node, key = _walk(data, parse_path(path), path)
    node[key] = copy.deepcopy(value)


def get_path(data: dict[str, Any], path: str) -> Any:
    """Value at ``path`` of the nested dict/list ``data`` (KeyError naming the missing part)."""
    node, key = _walk(data, parse_path(path), path)
    return node[key]


# ---------------------------------------------------------------------------- cases
@dataclass(frozen=True)
class Axis:
    """An axis with its values resolved (``labels`` are the coordinate values)."""

    name: str
    path: str
    values: tuple[Any, ...]
    labels: tuple[Any, ...]
    group: str
    units: str


@dataclass(frozen=True)
class Case:
    """One case: its index, seed, replicate and the value index of each axis."""

    index: int
    seed: int
    replicate: int
    value_index: tuple[int, ...]

    def values(self, axes: tuple[Axis, ...]) -> dict[str, Any]:
        return {a.name: a.values[j] for a, j in zip(axes, self.value_index, strict=True)}

    def labels(self, axes: tuple[Axis, ...]) -> dict[str, Any]:
        return {a.name: a.labels[j] for a, j in zip(axes, self.value_index, strict=True)}


def case_seed(sweep_seed: int, index: int) -> int:
    """Seed of case ``index`` of a sweep with seed ``sweep_seed``:
    ``SeedSequence([sweep_seed, index])``'s first 32-bit word (independent streams per case,
    the same whatever order or worker runs them; any case can be re-run alone)."""
    return int(np.random.SeedSequence([int(sweep_seed), int(index)]).generate_state(1)[0])


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _label(v: Any) -> Any:
    if isinstance(v, bool | int | float | str):
        return v
    return json.dumps(v, sort_keys=True, separators=(",", ":"))


def _draw(axes: list[AxisSpec], group: str, seed: int) -> dict[str, list[float]]:
    """Random values of the sampled axes of one group (seeded by sweep seed and group name)."""
    out: dict[str, list[float]] = {}
    gkey = int.from_bytes(hashlib.sha256(group.encode()).digest()[:4], "little")
    lhs = [a for a in axes if a.sample is not None and a.sample.method == "latin_hypercube"]
    if lhs:
        ns = {a.sample.n for a in lhs}  # type: ignore[union-attr]
        if len(ns) > 1:
            raise ConfigError(f"axes {', '.join(a.name for a in lhs)}: latin_hypercube axes of "
                              f"group '{group}' are drawn jointly and need one n (got "
                              f"{sorted(ns)})")
        from scipy.stats import qmc

        rng = np.random.default_rng(np.random.SeedSequence([seed, gkey, 0]))
        u = qmc.LatinHypercube(d=len(lhs), rng=rng).random(lhs[0].sample.n)  # type: ignore[union-attr]
        for j, a in enumerate(lhs):
            s = a.sample
            out[a.name] = [float(s.low + (s.high - s.low) * x) for x in u[:, j]]  # type: ignore[union-attr]
    for k, a in enumerate(axes):
        if a.sample is not None and a.sample.method == "uniform":
            rng = np.random.default_rng(np.random.SeedSequence([seed, gkey, k + 1]))
            s = a.sample
            out[a.name] = [float(x) for x in rng.uniform(s.low, s.high, s.n)]
    return out


def resolve_axes(spec: SweepSpec, base: dict[str, Any]) -> tuple[Axis, ...]:
    """Axes with their values (lists, ranges, draws) checked against the base config ``base``
    (the validated base config as a dict): the path must exist and scalar values must have the
    base value's type."""
    problems: list[str] = []
    limit = spec.sweep.max_cases
    for i, a in enumerate(spec.axes):  # sizes before any value is listed or drawn (issue 20)
        n = (a.range.count() if a.range is not None
             else float(a.sample.n) if a.sample is not None else float(len(a.values or [])))
        if n > limit:
            what = "range" if a.range is not None else "sample" if a.sample is not None else ""
            problems.append(f"axes[{i}]{'.' + what if what else ''} (axis '{a.name}'): "
                            f"{n:.12g} values, above sweep.max_cases = {limit} (every value is "
                            "at least one case); shrink the axis or raise sweep.max_cases")
    if problems:
        raise ConfigError(problems, source="sweep spec")
    groups: dict[str, list[AxisSpec]] = {}
    for a in spec.axes:
        groups.setdefault(a.group or f"axis:{a.name}", []).append(a)
    drawn: dict[str, list[float]] = {}
    for g, members in groups.items():
        try:
            drawn.update(_draw(members, g, spec.sweep.seed))
        except ConfigError as exc:
            problems.extend(exc.problems)
    axes: list[Axis] = []
    for a in spec.axes:
        where = f"axis '{a.name}' ({a.path})"
        values = (a.values if a.values is not None
                  else a.range.values() if a.range is not None else drawn.get(a.name, []))
        try:
            current = get_path(base, a.path)
        except ConfigError as exc:
            problems.append(f"{where}: {exc.problems[0]}")
            continue
        except KeyError as exc:
            problems.append(f"{where}: unknown path: {exc.args[0]}")
            continue
        for v in values:
            if _is_number(current) and not _is_number(v):
                problems.append(f"{where}: value {v!r} is not a number (the base config has "
                                f"{current!r})")
            elif isinstance(current, str) and not isinstance(v, str):
                problems.append(f"{where}: value {v!r} is not a string (the base config has "
                                f"{current!r})")
            elif isinstance(current, bool) and not isinstance(v, bool):
                problems.append(f"{where}: value {v!r} is not true/false")
            elif isinstance(current, list | dict) and not isinstance(v, type(current)):
                problems.append(f"{where}: value {v!r} is not a "
                                f"{'list' if isinstance(current, list) else 'table'} "
                                f"(the base config has {current!r})")
            elif isinstance(v, float) and not math.isfinite(v):
                problems.append(f"{where}: value {v!r} is not finite")
        if a.labels is not None and len(a.labels) != len(values):
            problems.append(f"{where}: {len(a.labels)} labels for {len(values)} values")
            continue
        labels = a.labels if a.labels is not None else [_label(v) for v in values]
        kinds = {type(x) for x in labels}
        if len(kinds) > 1 and not kinds <= {int, float}:
            labels = [str(x) for x in labels]
        axes.append(Axis(a.name, a.path, tuple(values), tuple(labels),
                         a.group or f"axis:{a.name}", a.units))
    for g, members in groups.items():
        sizes = {m.name: len(next(x for x in axes if x.name == m.name).values)
                 for m in members if any(x.name == m.name for x in axes)}
        if len(set(sizes.values())) > 1:
            problems.append(f"group '{g}': zipped axes need equal lengths, got "
                            + ", ".join(f"{k} {v}" for k, v in sizes.items()))
    if spec.sweep.combine == "zip":
        sizes = {a.name: len(a.values) for a in axes}
        if len(set(sizes.values())) > 1:
            problems.append("combine = 'zip': every axis needs the same number of values, got "
                            + ", ".join(f"{k} {v}" for k, v in sizes.items()))
    if problems:
        raise ConfigError(problems, source="sweep spec")
    return tuple(axes)


def combinations(spec: SweepSpec, axes: tuple[Axis, ...]) -> list[tuple[int, ...]]:
    """Value index of each axis for every combination (product of groups, first slowest; or
    one zip of every axis)."""
    if spec.sweep.combine == "zip":
        return [tuple(i for _ in axes) for i in range(len(axes[0].values))]
    order = list(dict.fromkeys(a.group for a in axes))
    sizes = [len(next(a for a in axes if a.group == g).values) for g in order]
    out = []
    for idx in itertools.product(*(range(n) for n in sizes)):
        pick = dict(zip(order, idx, strict=True))
        out.append(tuple(pick[a.group] for a in axes))
    return out


def count_cases(spec: SweepSpec, axes: tuple[Axis, ...]) -> int:
    """Number of cases (combinations × replicates) without listing them."""
    if spec.sweep.combine == "zip":
        n = len(axes[0].values)
    else:
        order = list(dict.fromkeys(a.group for a in axes))
        n = math.prod(len(next(a for a in axes if a.group == g).values) for g in order)
    return n * spec.sweep.replicates


# ---------------------------------------------------------------------------- loading
@dataclass(frozen=True)
class Sweep:
    """A validated sweep: spec, base config (as loaded and validated, as a dict), resolved axes,
    cases, and every case's config dict (validated)."""

    spec: SweepSpec
    spec_dict: dict[str, Any]
    base_path: Path
    base: dict[str, Any]
    base_hash: str
    axes: tuple[Axis, ...]
    cases: tuple[Case, ...]

    @property
    def spec_hash(self) -> str:
        """Hash of the spec and the base config: one store holds one sweep."""
        text = json.dumps({"spec": self.spec_dict, "base": self.base_hash}, sort_keys=True,
                          default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def case_config(self, case: Case) -> dict[str, Any]:
        """Config dict of ``case`` (the base with each axis value set)."""
        data = copy.deepcopy(self.base)
        for a, j in zip(self.axes, case.value_index, strict=True):
            set_path(data, a.path, a.values[j])
        return data


def _spec_error(exc: ValidationError, data: Mapping[str, Any], source: str) -> ConfigError:
    from geardyn.config.loader import format_validation_error

    return ConfigError(format_validation_error(exc, data), source=source)


def _axis_of(problem: str, axes: tuple[Axis, ...]) -> list[Axis]:
    """Axes whose path the config problem message starts with (longest match), else []."""
    field = problem.split(":", 1)[0]
    norm = re.sub(r" '[^']*'", "", field)
    hits = [a for a in axes if norm.startswith(re.sub(r"\[\s*[\"']([^\"']+)[\"']\s*\]",
                                                       r".\1", a.path))]
    return hits


def validate_cases(sweep: Sweep) -> None:
    """Validate every case's config as a config file (ConfigError naming the axis, its value
    and the case; each distinct problem reported once)."""
    from geardyn.config.loader import parse_config
    from geardyn.resources import run_problems

    run = sweep.spec.run
    seen: dict[str, str] = {}
    for case in sweep.cases:
        if case.replicate:
            continue
        try:
            cfg = parse_config(sweep.case_config(case))
            if run.t_end_s is not None or run.revolutions is not None:
                problems = run_problems(cfg, None, run.t_end_s, run.revolutions,
                                        t_end_name="run.t_end_s",
                                        revolutions_name="run.revolutions")
                if problems:
                    raise ConfigError(problems)
        except ConfigError as exc:
            vals = case.labels(sweep.axes)
            for p in exc.problems:
                hits = _axis_of(p, sweep.axes) or list(sweep.axes)
                named = ", ".join(f"axis '{a.name}' = {vals[a.name]!r}" for a in hits)
                key = f"{named}: {p}"
                seen.setdefault(key, f"case {case.index}: {key}")
            if len(seen) >= 20:
                break
    if seen:
        raise ConfigError(list(seen.values()), source="sweep spec (a case is invalid)")


def load_spec(path: str | Path, overrides: Mapping[str, Any] | None = None) -> Sweep:
    """Read, validate and expand the sweep spec at ``path`` (TOML). ``overrides``: a mapping
    merged into the spec's tables before validation (e.g. ``{"run": {"t_end_s": 2.0}}``)."""
    from geardyn.config.loader import check_path_length, read_toml

    p = Path(path)
    check_path_length(p, "sweep spec")
    if p.is_dir():
        raise ConfigError(f"sweep spec '{p}' is a directory, expected a TOML file")
    if not p.is_file():
        raise ConfigError(f"sweep spec '{p}' does not exist")
    data = read_toml(p, "sweep spec")  # UTF-8, TOML, nesting depth (issue 20)
    return from_dict(data, p.parent, overrides, source=str(p))


def _merge(a: dict[str, Any], b: Mapping[str, Any]) -> dict[str, Any]:
    out = dict(a)
    for k, v in b.items():
        out[k] = _merge(out[k], v) if isinstance(v, Mapping) and isinstance(out.get(k),
                                                                                dict) else v
    return out


def from_dict(data: Mapping[str, Any], root: str | Path = ".",
              overrides: Mapping[str, Any] | None = None, source: str = "sweep spec") -> Sweep:
    """Validate and expand a spec held in a mapping; ``root``: directory the base config path
    is relative to."""
    from geardyn.config.loader import load_config

    data = _merge(dict(data), overrides or {})
    if isinstance(data.get("run"), Mapping):  # "2 s" strings, implausible run lengths
        from geardyn.config.units import convert_units

        problems: list[str] = []
        data["run"] = convert_units(data["run"], "run", problems)
        if problems:
            raise ConfigError(problems, source=source)
    try:
        spec = SweepSpec.model_validate(data)
    except ValidationError as exc:
        raise _spec_error(exc, data, source) from None
    from geardyn.config.loader import check_path_length

    check_path_length(Path(root) / spec.sweep.base, "sweep.base")
    base_path = (Path(root) / spec.sweep.base).resolve()
    if not base_path.is_file():
        raise ConfigError(f"sweep.base: config file '{base_path}' does not exist", source=source)
    base_cfg = load_config(base_path)
    if spec.run.revolutions is not None and base_cfg.transmission is None:
        raise ConfigError("run.revolutions: sets the run length of the FE transmission model "
                          "([transmission] speed law); the base config has no [transmission]: "
                          "use run.t_end_s", source=source)
    base = base_cfg.model_dump(mode="json")
    base_hash = hashlib.sha256(base_path.read_bytes()).hexdigest()
    axes = resolve_axes(spec, base)
    n = count_cases(spec, axes)
    if n > spec.sweep.max_cases:
        sizes = " × ".join(f"{a.name} {len(a.values)}" for a in axes
                           if a.group == f"axis:{a.name}" or spec.sweep.combine == "product")
        raise ConfigError(f"sweep: {n} cases ({sizes} × {spec.sweep.replicates} replicates) "
                          f"exceed max_cases = {spec.sweep.max_cases}; shrink an axis or raise "
                          "sweep.max_cases", source=source)
    cases = []
    for k, idx in enumerate(combinations(spec, axes)):
        for r in range(spec.sweep.replicates):
            i = k * spec.sweep.replicates + r
            cases.append(Case(i, case_seed(spec.sweep.seed, i), r, idx))
    sweep = Sweep(spec, json.loads(json.dumps(data, default=str)), base_path, base, base_hash,
                  axes, tuple(cases))
    validate_cases(sweep)
    if spec.outputs.diagnosis is not None:
        sweep = _record_seeds(sweep, source)
    _check_outputs(sweep, base_cfg)
    _check_sizes(sweep, base_cfg)
    return sweep


def _record_seeds(sweep: Sweep, source: str) -> Sweep:
    """With ``[outputs.diagnosis]``: each case's seed is its config's ``diagnosis.
    record_seed`` (the record of ``geardyn diagnose``), which must not be a baseline seed."""
    from geardyn.config.diagnosis import DiagnosisSpec

    cases, problems = [], {}
    for case in sweep.cases:
        d = sweep.case_config(case).get("diagnosis")
        opts = DiagnosisSpec.model_validate(d) if d else DiagnosisSpec()
        seed = int(opts.record_seed)
        if seed in opts.baseline_seeds:
            vals = ", ".join(f"{k} = {v!r}" for k, v in case.labels(sweep.axes).items())
            key = (f"diagnosis.record_seed: {seed} is also a baseline seed "
                   f"{list(opts.baseline_seeds)}; the record must be an independent run")
            problems.setdefault(key, f"case {case.index} ({vals}): {key}")
        cases.append(Case(case.index, seed, case.replicate, case.value_index))
    if problems:
        raise ConfigError(list(problems.values()), source=source)
    return Sweep(sweep.spec, sweep.spec_dict, sweep.base_path, sweep.base, sweep.base_hash,
                 sweep.axes, tuple(cases))


def _check_sizes(sweep: Sweep, cfg: Any) -> None:
    """Resource estimates of the store before any case runs (:mod:`geardyn.resources`): the
    channel samples and the state grid of every case."""
    from geardyn.resources import bytes_problem

    out, n = sweep.spec.outputs, len(sweep.cases)
    problems = []
    if out.channels.names:
        p = bytes_problem("outputs.channels.samples", float(out.channels.samples) * n
                          * len(out.channels.names),
                          f"{out.channels.samples} samples × {len(out.channels.names)} "
                          f"channel(s) × {n} cases")
        if p:
            problems.append(p)
    if out.states.variables:
        sims = [getattr(getattr(cfg, sec, None), "simulation", None)
                for sec in ("planetary_dynamics", "dynamics")]
        ends = [sweep.spec.run.t_end_s or s.t_end_s for s in sims if s is not None]
        t_end = max(ends) if ends else 0.0
        points = t_end / out.states.step_s + 1
        p = bytes_problem("outputs.states.step_s", points * n * len(out.states.variables),
                          f"a {out.states.step_s:g} s grid over {t_end:g} s × "
                          f"{len(out.states.variables)} variable(s) × {n} cases")
        if p:
            problems.append(p)
    if problems:
        raise ConfigError(problems, source="sweep spec")


def _check_outputs(sweep: Sweep, cfg: Any) -> None:
    """Output channels must be sensors of the base config."""
    names = [s.name for s in getattr(cfg, "sensors", [])]
    out = sweep.spec.outputs
    problems = [f"outputs.channels.names: '{c}' is not a sensor of the base config "
                f"(sensors: {', '.join(names) or 'none'})"
                for c in out.channels.names if c not in names]
    ch = out.indicators.channel or (cfg.diagnosis.channel if cfg.diagnosis else None)
    if out.indicators.enabled and ch is not None and ch not in names:
        problems.append(f"outputs.indicators.channel: '{ch}' is not a sensor of the base config "
                        f"(sensors: {', '.join(names) or 'none'})")
    if out.indicators.enabled and not names:
        problems.append("outputs.indicators: the base config has no [[sensors]] to compute "
                        "indicators from; add one or set outputs.indicators.enabled = false")
    if out.verdicts is not None:
        for k, v in out.verdicts.healthy.items():
            axis = next(a for a in sweep.axes if a.name == k)
            if v not in axis.labels:
                problems.append(f"outputs.verdicts.healthy: {k} = {v!r} is not a value of axis "
                                f"'{k}' ({', '.join(map(repr, axis.labels))})")
        if not out.indicators.enabled:
            problems.append("outputs.verdicts: needs outputs.indicators.enabled = true")
    if problems:
        raise ConfigError(problems, source="sweep spec")
