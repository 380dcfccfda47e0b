"""A study of many machine configurations run as ``geardyn sweep`` specs.

:func:`specs` turns :class:`~geardyn.studies.runner.Configuration` s into sweep specs with
``[outputs.diagnosis]`` (:mod:`geardyn.sweep.diagnosis`: every case judged as ``geardyn
diagnose`` judges its config, against the baseline ensemble of its own healthy config). One
spec per base config and set of records (a planetary machine's configurations are grouped by
their faulty planet: the planet-crack record depends on it); each spec has two zipped axis
groups combined as a product:

* ``records`` (slowest): the faults of each record (the fault containers of the config —
  ``planetary_dynamics.stages[i].faults``, ``gear_geometry[j].cracks`` / ``.spalls``,
  ``transmission.bearings[k].outer_spall`` — set to the record's fault or to none) and its
  seed ``diagnosis.record_seed``, labelled ``record``, ``fault_type`` and ``severity``;
* ``configuration``: every config value the configuration changes (sensor, housing mode,
  noise, the operating point of :func:`geardyn.diagnosis.ensemble.operating_point`, the
  planetary run length of :func:`geardyn.sweep.verdicts.diagnosis_run_length_s`), labelled
  ``configuration`` (its id) and ``half`` (tune / report).

Records first: the first cases are one record of every configuration, so the workers start on
different configurations (each simulating its own baseline) instead of waiting for one.

:func:`write_specs` writes each spec as TOML next to its store (``OUT/<slug>.toml``,
``OUT/<slug>.zarr``): ``geardyn sweep OUT/<slug>.toml --out OUT/<slug>.zarr`` runs (or
resumes) it alone. :func:`rows` reads the stores back into the study's rows.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from geardyn.errors import ConfigError
from geardyn.studies.runner import Configuration, healthy_configuration

# ---- TOML ---------------------------------------------------------------------------------

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _toml_value(v: Any) -> str:  # noqa: ANN401
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise ValueError(f"not a finite number: {v!r}")
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise ValueError(f"no TOML form for {type(v).__name__} {v!r}")


def _toml_key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def toml_dumps(spec: Mapping[str, Any]) -> str:
    """A sweep spec (tables of scalars, ``axes`` an array of tables) as TOML text."""
    out: list[str] = []
    for name, table in spec.items():
        if name == "axes":
            continue
        _table(out, name, table)
    for axis in spec.get("axes", []):
        out.append("[[axes]]")
        out += [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in axis.items()]
        out.append("")
    return "\n".join(out)


def _table(out: list[str], name: str, table: Mapping[str, Any]) -> None:
    scalars = {k: v for k, v in table.items() if not isinstance(v, Mapping)}
    out.append(f"[{name}]")
    out += [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in scalars.items()]
    out.append("")
    for k, v in table.items():
        if isinstance(v, Mapping):
            _table(out, f"{name}.{_toml_key(k)}", v)


# ---- config paths ---------------------------------------------------------------------------


def _key(path: str, k: str) -> str:
    if re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", k):
        return f"{path}.{k}" if path else k
    return f'{path}["{k}"]'


def diff(a: Any, b: Any, path: str = "") -> dict[str, Any]:  # noqa: ANN401
    """Dotted paths (as sweep axes take them) where ``b`` differs from ``a`` → b's value:
    down to scalars through tables and equal-length lists of tables."""
    if isinstance(a, dict) and isinstance(b, dict) and set(a) == set(b):
        out: dict[str, Any] = {}
        for k in a:
            out.update(diff(a[k], b[k], _key(path, str(k))))
        return out
    if (
        isinstance(a, list)
        and isinstance(b, list)
        and len(a) == len(b)
        and all(isinstance(x, dict) for x in a + b)
    ):
        out = {}
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            out.update(diff(x, y, f"{path}[{i}]"))
        return out
    return {} if a == b else {path: b}


def fault_paths(data: Mapping[str, Any]) -> list[str]:
    """Paths of every fault container of a config dict (what
    :func:`geardyn.diagnosis.faults.healthy_variant` empties)."""
    out = [
        f"planetary_dynamics.stages[{i}].faults"
        for i, _ in enumerate((data.get("planetary_dynamics") or {}).get("stages", []))
    ]
    for j, _ in enumerate(data.get("gear_geometry") or []):
        out += [f"gear_geometry[{j}].cracks", f"gear_geometry[{j}].spalls"]
    for k, _ in enumerate((data.get("transmission") or {}).get("bearings") or []):
        out.append(f"transmission.bearings[{k}].outer_spall")
    return out


def _no_none(v: Any) -> Any:  # noqa: ANN401
    """``v`` without table entries that are None (TOML has no null: a field left out takes
    its default; :func:`specs` checks that every case config comes out as intended)."""
    if isinstance(v, dict):
        return {k: _no_none(x) for k, x in v.items() if x is not None}
    if isinstance(v, list):
        return [_no_none(x) for x in v]
    return v


def _parent(path: str) -> str:
    return re.sub(r"(\.[A-Za-z_][A-Za-z0-9_]*|\[[^\]]*\])$", "", path)


def _name(path: str, taken: set[str]) -> str:
    name = re.sub(r"[^A-Za-z0-9_]+", "_", path).strip("_") or "value"
    if name[0].isdigit():
        name = f"v_{name}"
    base, k = name, 1
    while name in taken:
        k += 1
        name = f"{base}_{k}"
    taken.add(name)
    return name


# ---- specs ------------------------------------------------------------------------------------


@dataclass
class StudySpec:
    """One sweep spec of a study: ``slug`` (file names), the spec (a dict), the
    configurations it holds."""

    slug: str
    spec: dict[str, Any]
    configurations: list[Configuration]


def _slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")


def configuration_config(
    conf: Configuration, extra: Mapping[str, Any] | None = None, run_length: bool = True
) -> Any:  # noqa: ANN401 - a GeardynConfig
    """The healthy config of ``conf`` (:func:`geardyn.studies.runner.healthy_configuration`,
    with ``extra`` path → value applied first) and, for a planetary machine when
    ``run_length``, ``planetary_dynamics.simulation.t_end_s`` set to what the verdict needs
    (:func:`geardyn.sweep.verdicts.diagnosis_run_length_s`, rounded up to 0.1 s)."""
    from dataclasses import replace

    from geardyn.config.loader import parse_config
    from geardyn.sweep.verdicts import diagnosis_run_length_s

    if extra:
        conf = replace(conf, update={**dict(conf.update), **dict(extra)})
    cfg = healthy_configuration(conf)
    if run_length and getattr(cfg, "planetary_dynamics", None) is not None:
        t = diagnosis_run_length_s(cfg)
        if t is not None:
            data = cfg.model_dump(mode="json")
            data["planetary_dynamics"]["simulation"]["t_end_s"] = math.ceil(t * 10.0) / 10.0
            cfg = parse_config(data, source=f"study configuration {conf.id}")
    return cfg


def specs(
    confs: Iterable[Configuration],
    *,
    seed: int = 0,
    diagnosis: Mapping[str, Any] | None = None,
    extra: Mapping[str, Mapping[str, Any]] | None = None,
    run_length: bool = True,
    check: bool = True,
) -> list[StudySpec]:
    """Sweep specs of the configurations ``confs`` (module docstring). ``diagnosis``: the
    ``[outputs.diagnosis]`` table; ``extra``: machine → (path → value) set on each
    configuration of that machine (a test's smaller baseline ensemble and shorter runs);
    ``run_length``: planetary run length from the verdict's requirement. ``check``: every
    case config of each spec is compared with the configuration's healthy config plus the
    record's faults (ConfigError naming the case when they differ)."""
    from geardyn.config.loader import load_config

    groups: dict[tuple[str, str, tuple], list[Configuration]] = {}
    for c in confs:
        recs = tuple(
            (r.label, r.fault_type, r.severity, json.dumps(dict(r.update), sort_keys=True), r.seed)
            for r in c.records
        )
        groups.setdefault((c.machine, c.base, recs), []).append(c)
    out = []
    taken_slugs: set[str] = set()  # one file per spec: a repeated slug would overwrite one
    for (machine, base_path, _), members in groups.items():
        base_cfg = load_config(base_path)
        base = base_cfg.model_dump(mode="json")
        from geardyn.diagnosis.faults import healthy_variant

        healthy_base = healthy_variant(base_cfg).model_dump(mode="json")
        faults = fault_paths(base)
        planets = {c.params.get("faulty_planet") for c in members}
        planet = planets.pop() if len(planets) == 1 and machine.startswith("planetary") else None
        slug = _slug(machine) + (f"-planet{planet}" if planet else "")
        if slug in taken_slugs:  # another record set of the same machine: its own files
            slug = f"{slug}-{sum(1 for t in taken_slugs if t.startswith(slug)) + 1}"
        taken_slugs.add(slug)
        records = members[0].records
        taken = {"case", "seed", "replicate", "status", "message"}
        axes: list[dict[str, Any]] = []
        # records: fault containers (lifted to their parent where a value is None) and seed
        paths = list(dict.fromkeys(faults + [p for r in records for p in r.update]))
        rec_values: dict[str, list[Any]] = {}
        from geardyn.sweep.spec import get_path, set_path

        def values_at(path: str, records: list = records, healthy: Any = healthy_base
                      ) -> list[Any]:  # the value at ``path`` in each record
            vals = []
            for r in records:
                data = json.loads(json.dumps(healthy))
                for k, v in r.update.items():
                    set_path(data, k, v)
                vals.append(get_path(data, path))
            return vals

        for p in paths:
            vals = values_at(p)
            if all(v == vals[0] for v in vals) and get_path(base, p) == vals[0]:
                continue  # the same in every record and in the base
            q = p
            while any(v is None for v in vals):
                q = _parent(q)
                vals = values_at(q)
            rec_values.setdefault(q, [_no_none(v) for v in vals])
        seeds = [int(r.seed) for r in records]
        taken |= {"record", "fault_type", "severity", "record_seed"}
        axes.append(
            {
                "name": "record_seed",
                "path": "diagnosis.record_seed",
                "values": seeds,
                "group": "records",
            }
        )
        for name, labels in (
            ("record", [r.label for r in records]),
            ("fault_type", [r.fault_type for r in records]),
            ("severity", [float(r.severity) for r in records]),
        ):
            # labels of the records (the seed set again: an axis needs a path)
            axes.append(
                {
                    "name": name,
                    "path": "diagnosis.record_seed",
                    "values": seeds,
                    "labels": labels,
                    "group": "records",
                }
            )
        for p, vals in rec_values.items():
            axes.append({"name": _name(p, taken), "path": p, "values": vals, "group": "records"})
        # configurations: every value each changes (not the fault containers)
        more = (extra or {}).get(machine)
        cfgs = [configuration_config(c, more, run_length) for c in members]
        diffs = []
        for cfg in cfgs:
            d = diff(base, cfg.model_dump(mode="json"))
            diffs.append(
                {
                    p: v
                    for p, v in d.items()
                    if not any(
                        p == f or p.startswith(f + "[") or p.startswith(f + ".") for f in faults
                    )
                }
            )
        cpaths = list(dict.fromkeys(p for d in diffs for p in d))
        conf_axes = []
        for p in cpaths:
            vals = [
                d.get(p, get_path(cfg.model_dump(mode="json"), p))
                for d, cfg in zip(diffs, cfgs, strict=True)
            ]
            if any(v is None for v in vals):
                raise ConfigError(
                    f"study configuration value at '{p}' is None in some "
                    "configuration (TOML has no null)"
                )
            conf_axes.append(
                {
                    "name": _name(p, taken),
                    "path": p,
                    "values": [_no_none(v) for v in vals],
                    "group": "configuration",
                }
            )
        if not conf_axes:
            raise ConfigError(f"{machine}: the configurations change nothing in the base config")
        lead = conf_axes[0]
        for name, labels in (
            ("configuration", [c.id for c in members]),
            ("half", [c.half for c in members]),
        ):
            axes.append(
                {
                    "name": name,
                    "path": lead["path"],
                    "values": lead["values"],
                    "labels": labels,
                    "group": "configuration",
                }
            )
        axes += conf_axes
        spec: dict[str, Any] = {
            "sweep": {
                "base": str(Path(base_path).resolve()),
                "name": f"detectability study: {machine}"
                + (f" (planet {planet} cracked)" if planet else ""),
                "seed": int(seed),
                "combine": "product",
                "max_cases": max(len(members) * len(records), 1),
            },
            "axes": axes,
            "outputs": {"indicators": {"enabled": False}, "diagnosis": dict(diagnosis or {})},
        }
        st = StudySpec(slug, spec, members)
        if check:
            _check(st, cfgs)
        out.append(st)
    return out


def _check(st: StudySpec, cfgs: list[Any]) -> None:  # noqa: ANN401
    """Every case config of the spec is the configuration's healthy config with the record's
    faults (as :func:`geardyn.studies.runner.run_configuration` built it)."""
    from geardyn.config.loader import parse_config
    from geardyn.sweep.spec import from_dict, set_path

    sweep = from_dict(st.spec, ".", source=f"study spec {st.slug}")
    ids = next(a for a in sweep.axes if a.name == "configuration")
    ci = {a.name: k for k, a in enumerate(sweep.axes)}
    for case in sweep.cases:
        conf_k = case.value_index[ci["configuration"]]
        rec_k = case.value_index[ci["record_seed"]]
        conf = st.configurations[conf_k]
        if ids.labels[conf_k] != conf.id:
            raise ConfigError(
                f"study spec {st.slug}: case {case.index} labelled "
                f"{ids.labels[conf_k]!r}, configuration {conf.id!r}"
            )
        rec = conf.records[rec_k]
        want = cfgs[conf_k].model_dump(mode="json")
        for p, v in rec.update.items():
            set_path(want, p, v)
        want["diagnosis"]["record_seed"] = int(rec.seed)
        want = parse_config(want).model_dump(mode="json")
        got = parse_config(sweep.case_config(case)).model_dump(mode="json")
        d = diff(want, got)
        if d:
            raise ConfigError(
                f"study spec {st.slug}: case {case.index} ({conf.id}, "
                f"{rec.label}) differs from its configuration at " + ", ".join(sorted(d)[:5])
            )


def write_specs(studies: list[StudySpec], out: str | Path) -> list[tuple[Path, Path]]:
    """Each spec as ``OUT/<slug>.toml`` (its store: ``OUT/<slug>.zarr``); returns the
    (spec, store) paths. A spec file that exists with other content is refused (its store
    holds another sweep)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for st in studies:
        p = out / f"{st.slug}.toml"
        text = (
            "# generated by geardyn.studies (the detectability study); run or resume alone "
            f"with:\n#   geardyn sweep {p.name} --out {st.slug}.zarr\n\n" + toml_dumps(st.spec)
        )
        store = out / f"{st.slug}.zarr"
        if store.exists() and p.exists() and p.read_text() != text:
            raise ConfigError(
                f"--out: {store} was made by another spec than this study's "
                f"{p.name} (the design or the options changed); choose a new "
                "folder (or delete it)"
            )
        p.write_text(text)
        paths.append((p, store))
    return paths


def run_specs(
    paths: list[tuple[Path, Path]],
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    only: set[str] | None = None,
    progress: Callable[[str], None] | None = None,
) -> None:
    """Run every spec into its store as ``geardyn sweep SPEC --out STORE`` does
    (:func:`geardyn.sweep.run`; resumable), on ``scheduler`` or a LocalCluster of
    ``workers``. ``only``: configuration ids to run (their cases; the others stay
    pending)."""
    from geardyn.sweep import load_spec, run

    for spec_path, store in paths:
        sweep = load_spec(spec_path)
        cases = None
        if only is not None:
            k = next(j for j, a in enumerate(sweep.axes) if a.name == "configuration")
            labels = sweep.axes[k].labels
            cases = [c.index for c in sweep.cases if labels[c.value_index[k]] in only]
            if not cases:
                continue

        def say(p: Any, name: str = spec_path.stem) -> None:  # noqa: ANN401
            if progress is not None:
                progress(f"{name}: {p.skipped + p.done}/{p.total} cases (failed {p.failed})")

        run(sweep, store, scheduler=scheduler, n_workers=workers, cases=cases, progress=say)


def _flag(v: float) -> bool | None:
    return None if not math.isfinite(v) else bool(v)


def rows(paths: list[tuple[Path, Path]], confs: Iterable[Configuration]) -> list[dict[str, Any]]:
    """The study's rows (as :func:`geardyn.studies.runner.run_configuration` wrote them)
    from the stores: one per stored case, its configuration's parameters and its
    ``diagnosis.*`` verdict."""
    from geardyn.sweep.store import open_dataset

    confs = list(confs)
    by_id = {c.id: c for c in confs}
    out: list[dict[str, Any]] = []
    for _spec, store in paths:
        if not store.exists():
            continue
        ds = open_dataset(store).load()
        for i in range(ds.sizes["case"]):
            status = str(ds["status"].values[i])
            if not status:
                continue  # pending
            conf = by_id.get(str(ds["configuration"].values[i]))
            if conf is None:
                continue
            label, seed = str(ds["record"].values[i]), int(ds["seed"].values[i])
            rec = next(r for r in conf.records if r.label == label and r.seed == seed)
            run_s = next(
                (
                    float(ds[a].values[i])
                    for a in ds.coords
                    if ds[a].attrs.get("path") == "planetary_dynamics.simulation.t_end_s"
                    and ds[a].dims == ("case",)
                ),
                math.nan,
            )
            d = {
                k: ds[f"diagnosis.{k}"].values[i]
                for k in (
                    "verdict",
                    "detected",
                    "location",
                    "localisation_level",
                    "localisation_state",
                    "confidence",
                    "localised",
                    "planet_named",
                    "expected",
                    "candidates",
                    "first_alarm",
                    "first_margin",
                    "tests",
                    "alpha_per_test",
                    "snr",
                    "cpu_s",
                    "baseline_cpu_s",
                )
            }
            row: dict[str, Any] = {
                "config": conf.id,
                "machine": conf.machine,
                "half": conf.half,
                "record": rec.label,
                "fault_type": rec.fault_type,
                "severity": float(rec.severity),
                "seed": int(rec.seed),
                "speed_factor": conf.speed_factor,
                "load_factor": conf.load_factor,
                **dict(conf.params),
                "run_s": run_s,
                "baseline_cpu_s": float(d["baseline_cpu_s"]),
            }
            if status == "ok":
                row.update(
                    {
                        "verdict": str(d["verdict"]),
                        "detected": bool(d["detected"] == 1.0),
                        "location": str(d["location"]),
                        "level": str(d["localisation_level"]),
                        "localisation": str(d["localisation_state"]),
                        "confidence": float(d["confidence"]),
                        "localised": _flag(float(d["localised"])),
                        "planet_named": _flag(float(d["planet_named"])),
                        "expected": str(d["expected"]),
                        "candidates": str(d["candidates"]),
                        "first_alarm": str(d["first_alarm"]),
                        "first_margin": float(d["first_margin"]),
                        "tests": int(d["tests"]),
                        "alpha_per_test": float(d["alpha_per_test"]),
                        "snr": float(d["snr"]),
                        "status": "ok",
                    }
                )
            else:
                msg = str(ds["message"].values[i]) or status
                row["status"] = f"failed: {msg}"
            row["record_cpu_s"] = float(d["cpu_s"])
            out.append(row)
    order = {c.id: k for k, c in enumerate(confs)}
    out.sort(
        key=lambda r: (
            order.get(r["config"], 0),
            r["fault_type"] != "healthy",
            r["record"],
            r["seed"],
        )
    )
    return out
