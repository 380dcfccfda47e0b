"""The layout of a sweep store, fixed before the first case runs, and the run-time checks.

:func:`plan` reads the spec and every case's own config (never a case's result) and returns
every per-case variable of the store with its dimensions, sizes, labels and units:

* channels: ``<name>.sample`` of ``outputs.channels.samples`` (the spec's bound on the samples
  kept per case); each case fills its first ``channels.<name>.length`` samples, NaN after;
* states: ``state_time`` up to the longest case's run (``[run].t_end_s`` or the case's
  ``planetary_dynamics.simulation.t_end_s``), ``shaft`` and ``mesh`` the union of the cases'
  model bodies and meshes (from the prepared model of each distinct case config);
* indicators: ``component`` the union of every case's diagnosable components
  (:func:`geardyn.diagnosis.components.machine_components`), ``indicator`` every detection
  indicator geardyn computes (:data:`geardyn.diagnosis.explain.INDICATORS`), ``block`` the
  configured number of blocks.

The same pass runs the checks a case would otherwise fail at run time (the time step:
planetary, against the model's shortest natural period and mesh period; FE transmission,
against the explicit stability limit and the mesh period —
:func:`geardyn.solve.sanity.check_time_step`; channel kinds) and predicts, from each case's
nominal input speed, the own revolutions of every component in the analysed record
(:func:`short_cases`): ``geardyn sweep --check`` reports both and nothing runs.
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from geardyn.errors import ConfigError, GeardynError

if TYPE_CHECKING:
    from geardyn.sweep.spec import Sweep

#: Dimensions whose labels are strings (matched by name when a case is written).
LABEL_DIMS = ("component", "indicator", "shaft", "mesh", "bearing_line", "domain")

#: Units of a sensor channel by kind (geardyn.sensors.channels): accelerometers read a force
#: [N] without a transfer path, an acceleration behind one.
_UNITS = {"encoder": "rad/s", "transmission_error": "rad", "tacho": "s"}


@dataclass
class Variable:
    """One per-case variable: dimensions after ``case``, attributes, and whether it holds
    strings."""

    dims: tuple[str, ...]
    attrs: dict[str, Any]
    text: bool = False


@dataclass
class Layout:
    """Every per-case variable, the size of every dimension and the labels of the labelled
    ones (``coords``: dim → (values, attrs)); ``notes``: warnings of the run-time checks."""

    variables: dict[str, Variable] = field(default_factory=dict)
    sizes: dict[str, int] = field(default_factory=dict)
    coords: dict[str, tuple[list[Any], dict[str, Any]]] = field(default_factory=dict)
    component_kind: dict[str, str] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def _distinct(sweep: Sweep) -> list[tuple[int, dict[str, Any]]]:
    """(first case index, config dict) of every distinct case config (replicates share)."""
    seen: set[str] = set()
    out = []
    for case in sweep.cases:
        if case.replicate:
            continue
        data = sweep.case_config(case)
        key = json.dumps(data, sort_keys=True, default=str)
        if key not in seen:
            seen.add(key)
            out.append((case.index, data))
    return out


def _without_faults(data: dict[str, Any]) -> dict[str, Any]:
    """The config dict with its faults removed (as :func:`geardyn.diagnosis.faults.
    healthy_variant`): the key of the time-step check. A crack or spall only lowers a
    stiffness, so the healthy model's natural periods are the shortest and its check the
    strictest; one check serves every fault of a machine and speed."""
    out = json.loads(json.dumps(data, default=str))
    for stage in (out.get("planetary_dynamics") or {}).get("stages", []):
        stage["faults"] = []
    for entry in out.get("gear_geometry", []) or []:
        entry["cracks"] = []
        entry["spalls"] = []
    for bearing in (out.get("transmission") or {}).get("bearings", []) or []:
        bearing["outer_spall"] = None
    return out


def _where(sweep: Sweep, index: int) -> str:
    vals = sweep.cases[index].labels(sweep.axes)
    return f"case {index} (" + ", ".join(f"{k} = {v!r}" for k, v in vals.items()) + ")"


def _t_end(sweep: Sweep, cfg: Any) -> float | None:
    pd = getattr(cfg, "planetary_dynamics", None)
    if pd is None or pd.simulation is None:
        return None
    diag = getattr(cfg, "diagnosis", None)  # [outputs.diagnosis]: the run of geardyn diagnose
    own = diag.t_end_s if diag is not None and sweep.spec.outputs.diagnosis is not None else None
    return float(sweep.spec.run.t_end_s or own or pd.simulation.t_end_s)


def _planetary_checks(cfg: Any, t_end: float) -> tuple[list[str], list[str], list[str]]:
    """Run-time checks of a planetary case before it runs (as :func:`geardyn.run.
    _planetary` does them): the time step (InputError → problem, TimeStepWarning → note).
    Returns (problems, shaft labels, mesh labels)."""
    from geardyn.models.planetary.build import prepare
    from geardyn.run import _planetary_speeds, body_links
    from geardyn.solve.sanity import check_time_step, mesh_period, shortest_period

    sim = cfg.planetary_dynamics.simulation
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        p = prepare(cfg, t_end_s=t_end)
        names = body_links(cfg, p.model)
        shafts = [names.get(b, b) for b in p.model.bodies]
        meshes = [p.model.springs[i].name for i in p.mesh_index]
        check_time_step(sim.dt_s, "planetary_dynamics.simulation.dt_s",
                        shortest_period(p.system),
                        mesh_period(p.system, _planetary_speeds(cfg, p)))
    notes = [str(w.message) for w in caught if "time step" in str(w.message)]
    return notes, shafts, meshes


def _transmission_checks(cfg: Any, data: dict[str, Any], cache: dict[str, float]
                         ) -> list[str]:
    """Run-time time-step check of an FE transmission case (as
    :func:`geardyn.models.transmission.simulate.simulate` with ``check_step``): the step
    against the explicit stability limit 2/ω_max and the mesh period at the speed law's
    largest speed. The stability limit needs the prepared model (static equilibrium, modes;
    seconds): computed once per machine (``cache``, keyed by the config without its speed
    law and simulation settings). Returns the coarse-step warnings."""
    from geardyn.models.transmission.assembly import build_model
    from geardyn.models.transmission.simulate import (
        _mesh_period,
        damping_operator,
        prepare,
        speed_ratios,
        with_mass,
    )
    from geardyn.solve.sanity import check_time_step

    t = cfg.transmission
    sl = t.speed_law
    if sl is None and (t.simulation.duration_s is None or t.simulation.initial_rpm is None):
        return []  # refused by the run itself with its own message (InputError)
    ref = sl.reference.shaft if sl is not None else t.drive.at.shaft
    model = with_mass(build_model(cfg), t)
    machine = json.loads(json.dumps(data, default=str))
    machine["transmission"].pop("speed_law", None)
    machine["transmission"].pop("simulation", None)
    key = json.dumps(machine, sort_keys=True)
    if key not in cache:
        _, cache[key] = damping_operator(prepare(model, ref),
                                         getattr(t, "modal_damping_cutoff_hz", None))
    dt_limit = cache[key]
    rpm = (max(abs(sl.start_rpm), abs(sl.end_rpm)) if sl is not None
           else abs(t.simulation.initial_rpm))
    dt = t.simulation.time_step_s or 0.8 * dt_limit
    field_name = ("transmission.simulation.time_step_s" if t.simulation.time_step_s
                  else "transmission.simulation.time_step_s (default: 0.8 × stability limit)")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_time_step(dt, field_name, mesh_period_s=_mesh_period(
            model, speed_ratios(model, ref), rpm * math.pi / 30), stable_limit_s=dt_limit)
    return [str(w.message) for w in caught if "time step" in str(w.message)]


def _indicator_names() -> list[str]:
    from geardyn.diagnosis.explain import INDICATORS
    from geardyn.diagnosis.verdict import is_isolation_measure

    names = INDICATORS.keys() if isinstance(INDICATORS, dict) else [i.name for i in INDICATORS]
    return sorted(n for n in names if not is_isolation_measure(n))


def _components(cfg: Any, ref: str | None) -> list[tuple[str, str, float]]:
    """(name, kind, |ratio| to ``ref``) of every diagnosable component of ``cfg``."""
    from geardyn.diagnosis.components import machine_components

    comps = machine_components(cfg, ref)
    return [(c.name, c.kind, float(c.abs_ratio)) for c in comps.items]


def isolation_orders() -> int:
    """Orders kept of each domain's per-order statistics: half the largest samples per
    revolution of :func:`geardyn.diagnosis.isolation.isolation_blocks`, plus order 0."""
    import inspect

    from geardyn.diagnosis.isolation import isolation_blocks

    spr = inspect.signature(isolation_blocks).parameters["max_samples_per_rev"].default
    return int(spr) // 2 + 1


def domain_labels(cfg: Any, ref: str | None, channel: str | None) -> list[str]:
    """Labels of the isolation domains a case of ``cfg`` can have (as :func:`geardyn.sweep.
    case._isolation` names them): the components sharing an own angle and mesh orders joined
    by ``+`` (the planets of a stage, say), ``TE:<wheel>`` for each wheel of a
    ``transmission_error`` channel's pair, ``planet:<name>`` for each planet (its
    planet-separated rows at a ring sensor)."""
    from geardyn.diagnosis.components import machine_components
    from geardyn.diagnosis.isolation import ROTATING

    comps = machine_components(cfg, ref)
    groups: dict[tuple, list[str]] = {}
    for c in comps.items:
        if c.kind in ROTATING and c.abs_ratio != 0.0:
            key = (f"{c.abs_ratio:.12g}", tuple(sorted({*c.mesh_orders, *c.other_orders})))
            groups.setdefault(key, []).append(c.name)
    out = ["+".join(sorted(v)) for v in groups.values()]
    names = {c.name for c in comps.items}
    graph = comps.analysis.graph if comps.analysis is not None else None
    for s in getattr(cfg, "sensors", []):
        if s.kind != "transmission_error" or graph is None:
            continue
        mesh = next((m for m in graph.meshes if m.name == s.pair), None)
        if mesh is None:
            continue
        for link, wheel, z in ((mesh.link_a, mesh.wheel_a, mesh.teeth_a),
                               (mesh.link_b, mesh.wheel_b, mesh.teeth_b)):
            w = wheel or f"{link}/z{z}"
            if w in names:
                out.append(f"TE:{w}")
    out += [f"planet:{c.name}" for c in comps.items if c.kind == "planet"]
    return out


def _reference(cfg: Any, channel: str | None, reference: str | None) -> str | None:
    """The reference link of the indicators (as :func:`geardyn.diagnosis.features.
    features_from_result`: the option, else the channel's shaft, else the first input)."""
    if reference:
        return reference
    sensor = next((s for s in getattr(cfg, "sensors", []) if s.name == channel), None)
    if sensor is not None and sensor.shaft:
        return sensor.shaft
    inputs = list(getattr(cfg, "input_speeds_rpm", {}) or {})
    return inputs[0] if inputs else None


@dataclass
class ShortCase:
    """A case whose record is too short for some components' statistics."""

    index: int
    components: dict[str, float]  # component → predicted own revolutions


def plan(sweep: Sweep) -> Layout:
    """The store layout of ``sweep`` and the run-time checks of every distinct case config;
    ConfigError naming the case(s) when a check fails."""
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis.pipeline import options

    spec = sweep.spec
    out = Layout()
    problems: list[str] = []
    shafts: set[str] = set()
    meshes: set[str] = set()
    comps: dict[str, str] = {}
    longest = 0.0
    planetary_all = True
    ind = spec.outputs.indicators
    n_blocks = None
    channel = ""
    domains: set[str] = set()
    checked: dict[str, str | None] = {}
    fe_cache: dict[str, float] = {}
    for index, data in _distinct(sweep):
        where = _where(sweep, index)
        cfg = parse_config(data, source=where)
        t_end = _t_end(sweep, cfg)
        if t_end is None:
            planetary_all = False
            if getattr(cfg, "transmission", None) is not None \
                    and getattr(cfg, "planetary_dynamics", None) is None:
                try:
                    healthy = _without_faults(data)
                    notes = _transmission_checks(parse_config(healthy, source=where),
                                                 healthy, fe_cache)
                except GeardynError as exc:
                    problems.append(f"{where}: {exc}")
                    continue
                out.notes.extend(f"{where}: {n}" for n in notes)
        else:
            longest = max(longest, t_end)
            healthy = _without_faults(data)
            key = json.dumps([healthy, t_end], sort_keys=True)
            if key not in checked:
                checked[key] = None
                try:
                    notes, sh, me = _planetary_checks(parse_config(healthy, source=where),
                                                      t_end)
                except GeardynError as exc:
                    checked[key] = str(exc)
                else:
                    out.notes.extend(f"{where}: {n}" for n in notes)
                    shafts.update(sh)
                    meshes.update(me)
            if checked[key] is not None:
                problems.append(f"{where}: {checked[key]}")
                continue
        if spec.run.revolutions is not None and t_end is not None:
            problems.append(f"{where}: run.revolutions applies to the FE transmission; the "
                            "planetary run length is run.t_end_s")
        if spec.outputs.diagnosis is not None:
            from geardyn.diagnosis.pipeline import check_ready

            try:
                check_ready(cfg, options(cfg))
            except GeardynError as exc:
                problems.append(f"{where}: outputs.diagnosis: {exc}")
                continue
        if ind.enabled:
            o = options(cfg, channel=ind.channel, skip_s=ind.skip_s, blocks=ind.blocks)
            n_blocks = o.blocks
            ch = o.channel or (cfg.sensors[0].name if cfg.sensors else None)
            channel = ch or ""
            sensor = next((s for s in cfg.sensors if s.name == ch), None)
            if sensor is not None and sensor.kind == "tacho":
                problems.append(f"{where}: outputs.indicators.channel: '{ch}' is a tacho "
                                "(pulse times, not a signal to diagnose); choose an "
                                "accelerometer, encoder or transmission_error channel")
                continue
            if t_end is not None and o.skip_s >= t_end:
                problems.append(f"{where}: outputs.indicators.skip_s = {o.skip_s:g} s leaves "
                                f"nothing of the {t_end:g} s run")
                continue
            try:
                ref = _reference(cfg, ch, o.reference)
                for name, kind, _r in _components(cfg, ref):
                    comps.setdefault(name, kind)
                if spec.outputs.verdicts is not None:
                    domains.update(domain_labels(cfg, ref, ch))
            except GeardynError as exc:
                problems.append(f"{where}: indicators: {exc}")
    if problems:
        raise ConfigError(problems[:20] + ([f"… and {len(problems) - 20} more"]
                                           if len(problems) > 20 else []),
                          source="sweep spec (run-time checks)")
    _channels(sweep, out)
    st = spec.outputs.states
    if st.variables:
        if not planetary_all:
            raise ConfigError("outputs.states: stored for the planetary model only (its state "
                              "grid is fixed by t_end_s); remove outputs.states for this model",
                              source="sweep spec")
        n = int(math.floor(longest / st.step_s + 1e-9)) + 1
        out.sizes["state_time"] = n
        out.coords["state_time"] = ([k * st.step_s for k in range(n)],
                                    {"units": "s", "long_name": "time of the state samples"})
        out.coords["shaft"] = (sorted(shafts), {"long_name": "shaft (model body)"})
        out.coords["mesh"] = (sorted(meshes), {"long_name": "gear mesh"})
        units = {"angle": "rad", "speed": "rad/s", "speed_rpm": "rpm", "mesh_force": "N"}
        for v in st.variables:
            other = "mesh" if v == "mesh_force" else "shaft"
            out.variables[f"state.{v}"] = Variable(
                ("state_time", other), {"units": units[v], "long_name": f"{v} on the state "
                                        "grid (NaN past a shorter run)"})
    if ind.enabled:
        names = sorted(comps)
        out.coords["component"] = (names, {"long_name": "diagnosable component"})
        out.component_kind = comps
        out.coords["indicator"] = (_indicator_names(), {"long_name": "condition indicator"})
        out.coords["block"] = (list(range(n_blocks or 1)), {"long_name": "block of whole "
                                                            "own revolutions"})
        out.variables["indicators"] = Variable(
            ("component", "indicator", "block"),
            {"units": "1", "long_name": f"condition indicators of channel {channel} per "
             "block", "channel": channel})
        from geardyn.diagnosis.components import BEARING_LINES

        out.coords["bearing_line"] = (list(BEARING_LINES), {"long_name": "bearing defect "
                                                            "line"})
        out.variables["band_energy"] = Variable(
            ("component", "bearing_line"),
            {"units": "1", "long_name": "fault-band energy share of the line's comb in the "
             "squared-envelope spectrum (bearings; MathWorks faultBandMetrics band power)"})
        if domains:
            out.coords["domain"] = (sorted(domains), {
                "long_name": "isolation domain: components sharing an own angle ('+'), the "
                             "transmission error of a wheel's mesh (TE:), a planet's "
                             "separated rows (planet:)"})
            out.sizes["order"] = isolation_orders()
            o_dims = ("domain", "order")
            u = _sensor_units(sweep.base, channel)
            out.variables["isolation.mean_real"] = Variable(o_dims, {
                "units": u, "long_name": "real part of the mean revolution's spectrum / spr "
                "(geardyn.diagnosis.isolation.order_stats); NaN past the case's orders"})
            out.variables["isolation.mean_imag"] = Variable(o_dims, {
                "units": u, "long_name": "imaginary part of the mean revolution's spectrum / "
                "spr"})
            out.variables["isolation.variance"] = Variable(o_dims, {
                "units": f"({u})^2", "long_name": "variance of the revolutions' spectra per "
                "order (ddof = 1)"})
            out.variables["isolation.ambiguous"] = Variable(o_dims, {
                "units": "1", "long_name": "1: order left out of the comparison (another "
                "member's harmonic within the TSA's resolution, geardyn.diagnosis.isolation."
                "ambiguous_orders); 0 compared; NaN none given"})
            out.variables["isolation.revolutions"] = Variable(("domain",), {
                "units": "1", "long_name": "whole own revolutions of the domain (NaN: fewer "
                "than 2)"})
        out.variables["revolutions"] = Variable(
            ("component",), {"units": "1", "long_name": "whole own revolutions of the "
                             "component in the analysed record (0: left out)"})
    if spec.outputs.diagnosis is not None:
        from geardyn.sweep.diagnosis import VARIABLES

        for name, (text, attrs) in VARIABLES.items():
            out.variables[f"diagnosis.{name}"] = Variable((), dict(attrs), text=text)
    for d, (labels, _a) in out.coords.items():
        out.sizes[d] = len(labels)
    return out


def _sensor_units(base: dict[str, Any], name: str) -> str:
    s = next((x for x in base.get("sensors", []) if x.get("name") == name), {})
    return _UNITS.get(s.get("kind", ""), "m/s^2" if s.get("transfer_path") else "N")


def _channels(sweep: Sweep, out: Layout) -> None:
    ch = sweep.spec.outputs.channels
    sensors = {s["name"]: s for s in sweep.base.get("sensors", [])}
    for name in ch.names:
        s = sensors.get(name, {})
        kind = s.get("kind", "")
        units = _sensor_units(sweep.base, name)
        sampling = {"encoder": "angle", "tacho": "events"}.get(kind, "time")
        dim = f"{name}.sample"
        out.sizes[dim] = ch.samples
        base = {"sensor_kind": kind, "sampling": sampling, "shaft": s.get("shaft") or ""}
        out.variables[f"channels.{name}"] = Variable(
            (dim,), {"units": units, "long_name": name, **base})
        out.variables[f"channels.{name}.time"] = Variable(
            (dim,), {"units": "s", "long_name": f"{name} sample time"})
        if sampling == "angle":
            out.variables[f"channels.{name}.angle"] = Variable(
                (dim,), {"units": "rad", "long_name": f"{name}: angle of shaft "
                                                      f"{s.get('shaft')}"})
        out.variables[f"channels.{name}.length"] = Variable(
            (), {"units": "1", "long_name": f"samples of {name} stored (the first of the "
                 "row; NaN after)"})
        out.variables[f"channels.{name}.samples_computed"] = Variable(
            (), {"units": "1", "long_name": f"samples of {name} after decimation, before "
                 f"keeping the last {ch.samples}"})


def short_cases(sweep: Sweep, minimum: float) -> list[ShortCase]:
    """Cases whose analysed record (run length − ``skip_s``) holds, at the case's nominal
    input speed, fewer than ``minimum`` own revolutions of some rotating component
    (prediction before the run; the stored ``revolutions`` are counted from the result)."""
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis.isolation import ROTATING
    from geardyn.diagnosis.pipeline import options

    ind = sweep.spec.outputs.indicators
    if not ind.enabled:
        return []
    out = []
    for index, data in _distinct(sweep):
        cfg = parse_config(data)
        t_end = _t_end(sweep, cfg)
        o = options(cfg, channel=ind.channel, skip_s=ind.skip_s, blocks=ind.blocks)
        ref = _reference(cfg, o.channel, o.reference)
        rpm = (getattr(cfg, "input_speeds_rpm", {}) or {}).get(ref)
        if t_end is None or rpm is None:
            continue
        ref_revs = max(t_end - o.skip_s, 0.0) * abs(float(rpm)) / 60.0
        try:
            comps = _components(cfg, ref)
        except GeardynError:
            continue
        short = {n: r * ref_revs for n, k, r in comps if k in ROTATING and r > 0
                 and r * ref_revs < minimum}
        if short:
            out.append(ShortCase(index, short))
    return out
