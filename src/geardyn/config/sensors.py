"""Config schema of the simulated sensors: ``[[sensors]]`` (issue 9).

Each sensor becomes a channel ``sensors.<name>`` of a simulation result (docs/results.md):

* ``encoder``: IAS of a shaft by the elapsed-time method (Thibault et al. 2024, eq 1):
  ``pulses_per_rev``,
  counter ``clock_hz`` (omit for an ideal clock), graduation errors (standard deviation
  ``graduation_error_rad``);
* ``tacho``: once-per-rev (or ``pulses_per_rev``) pulse times of a shaft;
* ``transmission_error``: an encoder (``pulses_per_rev``, ``clock_hz``) on each shaft of the
  gear ``pair`` and the angular transmission error of its wheel a,
  ``TE = θ_a − (z_b/z_a)·θ_b`` [rad] (both angles forward, from the latched edge times);
  a tooth fault shows in the TE of its own mesh only, which tells apart wheels sharing a shaft;
* ``accelerometer``: a force at a location through a transfer path, plus noise and ADC.
  Locations: ``ring`` of a planetary stage (ring-mounted sensor: the ring–planet mesh forces
  weighted by the planet-pass window of Hammami 2015, eqs 4.10-4.13), a bearing of the model
  (planetary: ``sun``/``carrier``/``ring``/``planetN`` body bearings, or a
  ``[[transmission.bearings]]`` name) in direction ``x`` or ``y``. ``transfer_path`` lists modes
  ``{frequency_hz, damping_ratio, modal_mass_kg}``; the accelerance of each is
  ``s²/(m(s² + 2ζωs + ω²))`` (a force on a single-DOF structure, m/s² per N). Without a path
  the channel is the force itself [N].

Noise (``noise_rms``, channel units) and the ADC (``adc_bits``, ``adc_full_scale``) follow; all
random draws use ``seed`` combined with the run seed, so the same config and seed give the same
bytes.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator


class _M(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


def _finite(v: float | None, name: str) -> float | None:
    if v is not None and not math.isfinite(v):
        raise ValueError(f"{name} must be a finite number, got {v}")
    return v


class TransferMode(_M):
    """One mode of a transfer path: accelerance s²/(m(s² + 2ζωs + ω²)) [m/s² per N]."""

    frequency_hz: float = Field(gt=0, description="natural frequency (Hz)")
    damping_ratio: float = Field(0.05, gt=0, lt=1)
    modal_mass_kg: float = Field(1.0, gt=0, description="modal mass (kg)")

    @field_validator("frequency_hz", "damping_ratio", "modal_mass_kg")
    @classmethod
    def _fin(cls, v: float, info) -> float:  # noqa: ANN001
        return _finite(v, info.field_name)  # type: ignore[return-value]


class SensorSpec(_M):
    """A simulated sensor (see the module docstring)."""

    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_\-]+$")
    kind: Literal["encoder", "tacho", "accelerometer", "transmission_error"]
    shaft: str | None = Field(
        None, description="encoder/tacho: the shaft measured; accelerometer: the shaft its "
        "order analysis refers to (default: the run's reference shaft)")
    location: str | None = Field(None, description="accelerometer: 'ring' or a bearing name")
    stage: str | None = Field(None, description="planetary stage of a ring sensor")
    pair: str | None = Field(None, description="transmission_error: gear pair name")
    direction: Literal["x", "y"] = "y"
    sensor_angle_deg: float = Field(0.0, description="ring sensor position (deg)")
    pulses_per_rev: int | None = Field(None, ge=1, le=100_000)
    clock_hz: float | None = Field(None, gt=0, description="encoder counter clock (Hz)")
    graduation_error_rad: float = Field(0.0, ge=0, description="encoder graduation error std")
    sample_rate_hz: float | None = Field(
        None, gt=0, description="accelerometer sample rate (default: the simulation's)")
    transfer_path: list[TransferMode] = Field(default_factory=list)
    noise_rms: float = Field(0.0, ge=0, description="white noise RMS (channel units)")
    adc_bits: int | None = Field(None, ge=2, le=32)
    adc_full_scale: float | None = Field(None, gt=0, description="ADC range ± (channel units)")
    seed: int = Field(0, ge=0)

    @field_validator("sensor_angle_deg", "clock_hz", "graduation_error_rad", "sample_rate_hz",
                     "noise_rms", "adc_full_scale")
    @classmethod
    def _fin(cls, v: float | None, info) -> float | None:  # noqa: ANN001
        return _finite(v, info.field_name)

    @model_validator(mode="after")
    def _check(self) -> SensorSpec:
        if self.kind == "transmission_error":
            if self.pair is None:
                raise ValueError(f"transmission_error '{self.name}' needs pair (a gear pair)")
            if self.location is not None or self.transfer_path:
                raise ValueError(f"transmission_error '{self.name}': location/transfer_path "
                                 "are for accelerometers")
        elif self.kind in ("encoder", "tacho"):
            if self.shaft is None:
                raise ValueError(f"{self.kind} '{self.name}' needs shaft (the shaft measured)")
            if self.location is not None or self.transfer_path:
                raise ValueError(f"{self.kind} '{self.name}': location/transfer_path are for "
                                 "accelerometers")
        else:
            if self.location is None:
                raise ValueError(f"accelerometer '{self.name}' needs location ('ring' or a "
                                 "bearing name)")
            if self.pulses_per_rev is not None or self.clock_hz is not None:
                raise ValueError(f"accelerometer '{self.name}': pulses_per_rev/clock_hz are "
                                 "for encoders and tachos")
        if self.kind == "encoder" and self.pulses_per_rev is not None and (
                self.graduation_error_rad >= math.pi / self.pulses_per_rev):
            raise ValueError("graduation_error_rad must stay below half a graduation "
                             "(π/pulses_per_rev)")
        return self

    @property
    def ppr(self) -> int:
        """Pulses per revolution (encoder default 1000, tacho 1)."""
        if self.pulses_per_rev is not None:
            return self.pulses_per_rev
        return 1 if self.kind == "tacho" else 1000


def model_names(cfg: object) -> tuple[set[str] | None, set[str] | None]:
    """Names a sensor may refer to before any model is built: shafts (mechanism links,
    planetary bodies — ``sun``, ``ring``, ``carrier``, ``planetN``, stage-prefixed when there
    are several stages —, rotors, FE shafts and their links) and accelerometer locations
    (``ring``, bearings of the mechanism, of the FE model and planetary bodies). None when a
    config section whose bodies are named at run time is present (``[dynamics]``: its shafts are
    the moving links and rotors, its accelerometer locations known only once it is built)."""
    dy = getattr(cfg, "dynamics", None)
    if dy is not None:
        frame = getattr(cfg, "frame", None)
        shafts = {lk.name for lk in getattr(cfg, "links", []) if lk.name != frame}
        return shafts | {r.name for r in dy.rotors}, None
    shafts = {lk.name for lk in getattr(cfg, "links", [])}
    locations = {"ring"} | {b.name for b in getattr(cfg, "bearings", []) if b.name}
    pd = getattr(cfg, "planetary_dynamics", None)
    if pd is not None:
        stages = {s.name: s for s in getattr(cfg, "planetary", [])}
        multi = len(pd.stages) > 1
        for sd in pd.stages:
            st = stages.get(sd.stage)
            pre = f"{sd.stage}." if multi else ""
            bodies = {pre + b for b in ("sun", "ring", "carrier")}
            if st is not None:
                bodies |= {f"{pre}planet{j + 1}" for j in range(st.n_planets)}
            shafts |= bodies
            locations |= bodies
        shafts |= {r.name for r in pd.rotors}
        locations |= {r.name for r in pd.rotors}
    tr = getattr(cfg, "transmission", None)
    if tr is not None:
        shafts |= {s.name for s in tr.shafts} | {s.link for s in tr.shafts if s.link}
        locations |= {b.name for b in tr.bearings}
    return shafts, locations


def sensor_name_problems(cfg: object) -> list[str]:
    """Sensors whose shaft or location is none of :func:`model_names` (the commands that run
    a model call this before the run; the run checks again against the built model)."""
    shafts, locations = model_names(cfg)
    problems: list[str] = []
    for i, s in enumerate(getattr(cfg, "sensors", [])):
        where = f"sensors[{i}] '{s.name}'"
        if shafts is not None and s.shaft is not None and s.shaft not in shafts:
            problems.append(f"{where}.shaft: '{s.shaft}' is not a shaft of the model (shafts: "
                            f"{', '.join(sorted(shafts))})")
        if locations is not None and s.kind == "accelerometer" and s.location is not None \
                and s.location not in locations:
            problems.append(f"{where}.location: unknown location '{s.location}' (locations: "
                            f"{', '.join(sorted(locations))})")
    return problems


def check_sensors(cfg: object) -> list[str]:
    """Cross-checks: unique names, stages that exist in the mechanism (shafts and locations:
    :func:`sensor_name_problems`, and against the model when the run starts)."""
    sensors: list[SensorSpec] = getattr(cfg, "sensors", [])
    problems: list[str] = []
    stages = {s.name for s in getattr(cfg, "planetary", [])}
    seen: set[str] = set()
    for i, s in enumerate(sensors):
        where = f"sensors[{i}] '{s.name}'"
        if s.name in seen:
            problems.append(f"{where}.name: duplicate sensor name")
        seen.add(s.name)
        pairs = {p.label for p in getattr(cfg, "gear_pairs", [])}
        for st in ("parallel", "bevel"):
            pairs |= {p.name for p in getattr(cfg, st, [])}
        if s.pair is not None and s.pair not in pairs:
            problems.append(f"{where}.pair: unknown gear pair '{s.pair}' (pairs: "
                            f"{', '.join(sorted(pairs)) or 'none'})")
        if s.stage is not None and s.stage not in stages:
            problems.append(f"{where}.stage: unknown planetary stage '{s.stage}' (stages: "
                            f"{', '.join(sorted(stages)) or 'none'})")
        if s.kind == "accelerometer" and s.location == "ring" and s.stage is None and \
                len(stages) != 1:
            problems.append(f"{where}.stage: name the planetary stage of the ring sensor "
                            f"(stages: {', '.join(sorted(stages)) or 'none'})")
    return problems
