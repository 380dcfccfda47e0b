"""Verdict per component: a record's indicators against the baseline thresholds.

For each ``(component, indicator, channel)`` the record value is the median over the record's
blocks of whole revolutions. An indicator alarms when it exceeds its upper threshold (or leaves
the band of a two-sided one); a component is ``alarm`` when any of its indicators alarms,
``healthy`` when it has at least one usable indicator and none alarms, and ``unknown`` when no
indicator of it could be judged (no value, or no usable baseline threshold).

Margin: ``value / threshold`` for higher-is-worse indicators (> 1 ⇔ alarm); for a threshold
≤ 0, ``(value − mean) / (k·σ)``; for two-sided indicators ``|value − mean| / (k·σ)`` (> 1 ⇔
alarm in every case).

:meth:`Verdict.write` stores ``verdict.json`` (schema ``geardyn.verdict/1``, see
docs/diagnosis.md).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from geardyn.checkpoint import write_text
from geardyn.diagnosis.baseline import KEYS, ThresholdRule, check_table, direction
from geardyn.diagnosis.faults import ConfiguredFault

SCHEMA = "geardyn.verdict/1"
STATES = ("healthy", "alarm", "uncertain", "unknown")


@dataclass(frozen=True)
class IndicatorVerdict:
    """One indicator of one component: record value, baseline statistics and threshold."""

    value: float
    threshold: float
    lower: float | None
    mean: float
    std: float
    sigma: float
    n: int
    margin: float
    alarm: bool
    direction: str
    channel: str


@dataclass
class ComponentVerdict:
    """State of one component and its indicators (keyed by indicator name, or
    ``'channel:indicator'`` when several channels are judged)."""

    component: str
    kind: str
    state: str
    indicators: dict[str, IndicatorVerdict] = field(default_factory=dict)

    @property
    def alarms(self) -> list[str]:
        """Names of the indicators in alarm."""
        return [k for k, v in self.indicators.items() if v.alarm]

    @property
    def worst(self) -> tuple[str, float] | None:
        """``(indicator, margin)`` of the detection indicator (isolation evidence excluded)
        with the largest finite margin, or None."""
        items = [(k, v.margin) for k, v in self.indicators.items()
                 if math.isfinite(v.margin) and not is_isolation_measure(k)]
        return max(items, key=lambda kv: kv[1]) if items else None

    @property
    def isolation(self) -> tuple[str, float] | None:
        """``(measure, margin)`` of the isolation evidence (:data:`isolation measure
        <is_isolation_measure>`) that decided the state, or None."""
        items = [(k, v.margin) for k, v in self.indicators.items() if is_isolation_measure(k)]
        return max(items, key=lambda kv: kv[1]) if items else None


def is_isolation_measure(name: str) -> bool:
    """True for the isolation evidence that :func:`geardyn.diagnosis.localise.localise` adds:
    the coherent synchronous deviation ratios ``cSDR``/``cSDR_*`` (and the older ``SDR``
    names), bearing fault-band energies ``'<LINE> band energy'`` and line-comb
    concentrations ``'<LINE> concentration'``."""
    key = name.rpartition(":")[2]
    return (key in ("SDR", "cSDR") or key.startswith(("SDR_", "cSDR_"))
            or key.endswith((" concentration", " band energy")))


@dataclass
class Verdict:
    """Verdict of one record: per-component states and the context they were judged in."""

    machine: str
    channels: list[str]
    rule: ThresholdRule
    components: dict[str, ComponentVerdict]
    baseline: dict[str, Any] = field(default_factory=dict)
    record: dict[str, Any] = field(default_factory=dict)
    expected_faults: list[ConfiguredFault] | None = None
    """Faults configured in the record (None: not known, e.g. a measured record)."""
    notes: list[str] = field(default_factory=list)
    """Why components or indicators could not be judged (e.g. too few revolutions)."""
    detection: dict[str, Any] | None = None
    """Machine-level detection (:func:`geardyn.diagnosis.localise.localise`): ``detected``,
    ``false_alarm_probability``, ``tests``, ``alpha_per_test``, ``alarms``."""
    localisation: dict[str, Any] | None = None
    """Location of a detected fault: ``state`` (``localised``, ``uncertain``, ``none``),
    ``level``, ``components``, ``confidence`` (posterior), ``candidates``, ``score``."""
    stages: dict[str, str] = field(default_factory=dict)
    """Planetary stage of each planet (the planet set is one location)."""
    provenance: dict[str, Any] = field(default_factory=dict)
    """Who made the verdict, when and at which operating point (:func:`provenance`):
    ``geardyn_version``, ``created_utc``, ``config`` (file and sha256 of its bytes),
    ``operating_point``; written at the top of verdict.json with :data:`UNITS`."""

    @property
    def alarms(self) -> list[str]:
        """Components in alarm."""
        return [c for c, v in self.components.items() if v.state == "alarm"]

    @property
    def state(self) -> str:
        """Machine verdict: ``alarm`` (detected and localised), ``uncertain`` (detected, location
        uncertain) or ``healthy`` (nothing detected; components not judged are listed
        ``unknown``). Without a detection step (plain :func:`judge`): ``alarm`` when any
        component alarms."""
        if self.detection is None:
            return "alarm" if self.alarms else "healthy"
        if not self.detection.get("detected"):
            return "healthy"
        loc = self.localisation or {}
        return "alarm" if loc.get("state") == "localised" else "uncertain"

    @property
    def location(self) -> list[str]:
        """Components the fault is localised to (empty unless localised)."""
        if self.localisation is None:
            return self.alarms
        return list(self.localisation.get("components") or [])

    def summary(self) -> dict[str, Any]:
        """Machine ``verdict`` (:attr:`state`), ``location`` and its ``confidence``,
        ``candidates`` when uncertain, counts, alarms and (with configured faults) whether the
        location matches them: ``missed`` faulty components not covered by the location,
        ``unexpected`` location components elsewhere — the shaft carrying a faulty wheel or
        bearing, and the other planets of a planet set holding a faulty planet, are not
        unexpected —, ``localised`` (detected, located, none missed, none unexpected) and
        ``planet_named`` (a faulty planet named alone; null without a planet fault)."""
        from geardyn.diagnosis.localise import expected_match

        states = [v.state for v in self.components.values()]
        loc = self.localisation or {}
        out: dict[str, Any] = {
            "verdict": self.state,
            "detected": self.state != "healthy",
            "location": self.location,
            "confidence": loc.get("confidence"),
            "candidates": [c["component"] for c in loc.get("candidates", [])]
            if self.state == "uncertain" else [],
            "alarms": self.alarms,
            "counts": {s: states.count(s) for s in STATES},
        }
        if self.expected_faults is not None:
            expected = sorted({f.component for f in self.expected_faults})
            carriers = {f.shaft for f in self.expected_faults if f.shaft}
            kinds = {n: c.kind for n, c in self.components.items()}
            m = expected_match(self.location, expected, carriers, kinds, self.stages)
            out["expected"] = expected
            out.update(m)
            out["localised"] = (self.state == "alarm" and not m["missed"]
                                and not m["unexpected"]) if expected else self.state == "healthy"
        return out

    def table(self) -> pd.DataFrame:
        """One row per component: ``component, kind, state, worst_indicator, margin,
        isolation, isolation_margin`` (worst indicator of all; isolation evidence if any)."""
        rows = []
        for name, c in self.components.items():
            w, iso = c.worst, c.isolation
            rows.append({"component": name, "kind": c.kind, "state": c.state,
                         "worst_indicator": w[0] if w else "",
                         "margin": w[1] if w else math.nan,
                         "isolation": iso[0] if iso else "",
                         "isolation_margin": iso[1] if iso else math.nan})
        return pd.DataFrame(rows, columns=["component", "kind", "state", "worst_indicator",
                                           "margin", "isolation", "isolation_margin"])

    def indicator_table(self) -> pd.DataFrame:
        """One row per judged indicator: component, kind, indicator, channel, value, mean, std,
        sigma, lower, threshold, margin, alarm."""
        rows = [
            {"component": name, "kind": c.kind, "indicator": key, **asdict(v)}
            for name, c in self.components.items()
            for key, v in c.indicators.items()
        ]
        cols = ["component", "kind", "indicator", "channel", "value", "mean", "std", "sigma",
                "lower", "threshold", "margin", "alarm"]
        return pd.DataFrame(rows, columns=cols) if rows else pd.DataFrame(columns=cols)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (schema ``geardyn.verdict/1``; NaN → null)."""
        comps = {}
        for name, c in self.components.items():
            w = c.worst
            comps[name] = {
                "kind": c.kind,
                "state": c.state,
                "alarms": c.alarms,
                "worst": {"indicator": w[0], "margin": w[1]} if w else None,
                "indicators": {k: asdict(v) for k, v in c.indicators.items()},
            }
        out = {
            "schema": SCHEMA,
            **self.provenance,
            "units": UNITS,
            "machine": self.machine,
            "channels": list(self.channels),
            "rule": self.rule.describe(),
            "k": self.rule.k,
            "sigma_floor": self.rule.sigma_floor,
            "baseline": self.baseline,
            "record": self.record,
            "expected_faults": (None if self.expected_faults is None
                                else [asdict(f) for f in self.expected_faults]),
            "components": comps,
            "notes": list(self.notes),
            "detection": self.detection,
            "localisation": self.localisation,
            "summary": self.summary(),
            "indicator_definitions": _definitions(
                {k.rpartition(":")[2] for c in self.components.values() for k in c.indicators}),
        }
        return _clean(out)

    def write(self, path: str | Path) -> Path:
        """Write ``verdict.json`` (or ``path`` itself if it ends in ``.json``)."""
        p = Path(path)
        if p.suffix != ".json":
            p = p / "verdict.json"
        write_text(p, json.dumps(self.to_dict(), indent=2, ensure_ascii=False) + "\n")
        return p


#: Units of the numbers of verdict.json ("1": dimensionless). Indicator values, means, standard
#: deviations, σ and thresholds carry the unit of their indicator:
#: ``indicator_definitions[NAME].unit``.
UNITS: dict[str, str] = {
    "k": "1 (threshold factor: threshold = mean + k·sigma)",
    "sigma_floor": "1 (fraction of |mean|)",
    "margin": "1 (value / threshold; alarm above 1)",
    "indicator value, mean, std, sigma, lower, threshold": "unit of the indicator "
    "(indicator_definitions[NAME].unit)",
    "n": "1 (count of baseline samples pooled)",
    "false_alarm_probability": "1 (probability per machine)",
    "alpha_per_test": "1 (probability per test)",
    "confidence": "1 (posterior probability)",
    "t_end_s, skip_s": "s",
    "input_speeds": "rpm",
}


def provenance(cfg: Any, config_file: str | Path | None = None) -> dict[str, Any]:
    """The provenance block of verdict.json: geardyn version, UTC time of the verdict (ISO
    8601), the config file and the SHA-256 of its bytes (when the verdict comes from a file),
    and the operating point stated in the config (input speeds in rpm)."""
    import datetime
    import hashlib

    import geardyn

    out: dict[str, Any] = {
        "geardyn_version": geardyn.__version__,
        "created_utc": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
    }
    if config_file is not None:
        p = Path(config_file)
        out["config"] = {"file": str(p), "sha256": hashlib.sha256(p.read_bytes()).hexdigest()}
    speeds = dict(getattr(cfg, "input_speeds_rpm", None) or {})
    out["operating_point"] = {
        "input_speeds": {k: {"value": float(v), "unit": "rpm"} for k, v in speeds.items()},
        "source": "the config's input_speeds_rpm (nominal; baseline members vary them, see "
                  "baseline.members)"}
    return out


def _definitions(names: set[str]) -> dict[str, Any]:
    """Definition, unit and reference of every indicator name (docs/indicators.md)."""
    try:
        from geardyn.diagnosis.explain import explain
    except ImportError:
        return {}
    out = {}
    for n in sorted(names):
        e = explain(n)
        if e is not None:
            out[n] = {k: v for k, v in asdict(e).items() if k != "name"}
    return out


def _clean(obj: Any) -> Any:
    """NaN/inf → None and numpy scalars → Python, recursively (strict JSON)."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _margin(value: float, th: pd.Series, k: float) -> float:
    """value/threshold (upper, threshold > 0); (value − μ)/(kσ) (upper, threshold ≤ 0);
    |value − μ|/(kσ) (two-sided): > 1 exactly when the indicator alarms."""
    dev = (value - float(th["mean"])) / (k * float(th["sigma"]))
    if th["direction"] == "upper":
        return value / float(th["upper"]) if th["upper"] > 0 else dev
    return abs(dev)


def _alarm(value: float, th: pd.Series) -> bool:
    if value > th["upper"]:
        return True
    return th["direction"] == "two-sided" and value < th["lower"]


def record_values(record: pd.DataFrame) -> pd.DataFrame:
    """Median over the blocks of a record per ``(component, kind, indicator, channel)``
    (non-finite values ignored; NaN when none is finite)."""
    rows = check_table(record, "record table")
    rows = rows[np.isfinite(rows["value"])]
    return rows.groupby(KEYS, sort=False)["value"].median().reset_index()


def judge(
    record: pd.DataFrame,
    thresholds: pd.DataFrame,
    rule: ThresholdRule,
    *,
    machine: str = "",
    baseline: dict[str, Any] | None = None,
    record_info: dict[str, Any] | None = None,
    expected_faults: Sequence[ConfiguredFault] | None = None,
    components: Sequence[tuple[str, str]] = (),
    notes: Sequence[str] = (),
) -> Verdict:
    """Verdict of a record's indicator table against thresholds from
    :func:`geardyn.diagnosis.baseline.thresholds` (computed with the same ``rule``).

    ``components``: ``(name, kind)`` of every component of the machine, so that one missing
    from both tables (not analysed) is reported ``unknown`` rather than left out; ``notes``
    say why (kept in the verdict)."""
    values = record_values(record)
    th = thresholds.set_index(KEYS)
    channels = sorted(set(values["channel"]) | set(thresholds["channel"]))
    multi = len(channels) > 1
    comps: dict[str, ComponentVerdict] = {}
    table = check_table(record)
    order = list(dict.fromkeys([*(c for c, _ in components), *thresholds["component"],
                                *table["component"]]))
    kinds = dict(components)
    kinds.update(dict(zip(thresholds["component"], thresholds["kind"], strict=False)))
    kinds.update(dict(zip(table["component"], table["kind"], strict=False)))
    for name in order:
        comps[name] = ComponentVerdict(str(name), str(kinds[name]), "unknown")
    for _, r in values.iterrows():
        key = (r["component"], r["kind"], r["indicator"], r["channel"])
        if direction(str(r["indicator"])) == "none" or key not in th.index:
            continue
        t = th.loc[key]
        if not bool(t["usable"]):
            continue
        value = float(r["value"])
        iv = IndicatorVerdict(
            value=value,
            threshold=float(t["upper"]),
            lower=None if t["direction"] == "upper" else float(t["lower"]),
            mean=float(t["mean"]), std=float(t["std"]), sigma=float(t["sigma"]), n=int(t["n"]),
            margin=_margin(value, t, rule.k), alarm=bool(_alarm(value, t)),
            direction=str(t["direction"]), channel=str(r["channel"]),
        )
        name = f"{r['channel']}:{r['indicator']}" if multi else str(r["indicator"])
        comps[r["component"]].indicators[name] = iv
    for c in comps.values():
        if c.indicators:
            c.state = "alarm" if c.alarms else "healthy"
    return Verdict(
        machine=machine, channels=channels, rule=rule, components=comps,
        baseline=dict(baseline or {}), record=dict(record_info or {}),
        expected_faults=None if expected_faults is None else list(expected_faults),
        notes=list(notes),
    )


def read_verdict(path: str | Path) -> dict[str, Any]:
    """A ``verdict.json`` as a dictionary (``path`` a file or the directory holding it)."""
    p = Path(path)
    return json.loads((p / "verdict.json" if p.is_dir() else p).read_text())
