"""Config schema of measured records: the optional ``[measurement]`` section (issue 19).

It maps the channels of a measured file (CSV, WAV, MAT, TDMS, UFF, MDF, HDF5/NetCDF…: read by
:func:`geardyn.io.read_record`) onto the model, so that a measured record reaches the same
result layout as a simulated run (docs/results.md) and the diagnosis sees the same components:

* ``[[measurement.channels]]``: the file channel (``source``: column name or index, TDMS
  ``group/channel``, MAT variable, HDF5 dataset path, UFF ``id1``, MDF channel name) → the
  record channel ``name`` (give it the name of the ``[[sensors]]`` entry it corresponds to, so
  that simulated baselines are compared channel by channel), its ``kind`` and where it sits on
  the model with the names ``[[sensors]]`` uses (``location`` ``ring`` with its ``stage``, or a
  bearing; ``direction``; ``shaft``), its units and sensitivity: the file's values
  [``file_units``] ÷ ``sensitivity`` give the channel in ``units`` (``"100 mV/g"`` with the
  file in V gives m/s²; ``g`` in a sensitivity is standard gravity, 9.80665 m/s²); for audio
  files ``full_scale`` is the quantity at digital full scale (``"10 V"``);
* the speed: a ``tacho`` channel (analog: a rising edge crosses ``threshold`` + ``hysteresis``/2
  after being below ``threshold`` − ``hysteresis``/2; the edge time is where it crosses
  ``threshold``, interpolated: MATLAB ``tachorpm``; ``pulses_per_rev``), an ``encoder`` channel
  (the same edge detection with the encoder's lines per revolution; its IAS becomes a channel),
  or ``profile_rpm`` (``[[t_s, rpm], …]``, piecewise linear) or a constant ``speed_rpm`` of
  ``speed_shaft``;
* the record's timestamp and operating point (``speed_rpm``, ``load_nm``), and the sample rate
  when the file states none (``sample_rate_hz``; a file that states one must agree with it).
"""

from __future__ import annotations

import datetime as dt
import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

#: Units a channel of each kind has by default (after the sensitivity).
DEFAULT_UNITS = {"accelerometer": "m/s^2", "velocity": "m/s", "displacement": "m",
                 "microphone": "Pa", "tacho": "V", "encoder": "V"}


class _M(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


def parse_quantity(text: str, what: str):  # noqa: ANN201 - pint.Quantity
    """``text`` as a pint quantity; ``g`` alone is standard gravity (an accelerometer
    sensitivity in mV/g); ValueError naming the rule."""
    import re

    from geardyn.config.units import registry

    ureg = registry()
    s = re.sub(r"(?<![A-Za-z_])g(?![A-Za-z_0-9])", "g_n", str(text))
    try:
        q = ureg.Quantity(s.strip())
    except Exception as exc:  # noqa: BLE001 - pint raises PintError, SyntaxError, even
        # AssertionError on a dangling operator ("100 mV/")
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ValueError(f"{text!r} is not {what} (pint: {why})") from None
    if not isinstance(q, ureg.Quantity):
        q = ureg.Quantity(float(q), "")
    if not math.isfinite(float(q.magnitude)):
        raise ValueError(f"{text!r} is not a finite number")
    return q


class MeasuredChannel(_M):
    """One file channel mapped onto the model (see the module docstring)."""

    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_\-]+$",
                      description="channel name in the record (sensors.<name>); the name of "
                      "the [[sensors]] entry it corresponds to when compared with simulations")
    source: str | int | None = Field(
        None, description="file channel: column name or 0-based index, TDMS 'group/channel', "
        "MAT variable, HDF5 dataset path, UFF id1, MDF channel name (default: name)")
    kind: Literal["accelerometer", "velocity", "displacement", "microphone", "tacho",
                  "encoder"] = Field("accelerometer", description="what the channel measures "
                                     "(tacho/encoder: a speed reference, not a signal)")
    location: str | None = Field(None, description="accelerometer: 'ring' or a bearing name "
                                 "(the names [[sensors]] uses)")
    stage: str | None = Field(None, description="planetary stage of a ring sensor")
    direction: Literal["x", "y", "z", "axial", "radial"] = Field(
        "y", description="measuring direction at a bearing (x, y as [[sensors]])")
    shaft: str | None = Field(None, description="tacho/encoder: the shaft measured; others: "
                              "the shaft orders refer to (default: the speed shaft)")
    sensor_angle_deg: float = Field(0.0, description="ring sensor position (deg)")
    units: str | None = Field(None, description="units of the channel after the sensitivity "
                              "(default: m/s^2 for an accelerometer, m/s velocity, m "
                              "displacement, Pa microphone, the file's for tacho/encoder)")
    file_units: str | None = Field(None, description="units of the values in the file "
                                   "(default: as the file states, V with a sensitivity)")
    sensitivity: str | None = Field(None, description="transducer sensitivity with its unit, "
                                    "e.g. \"100 mV/g\" (g = 9.80665 m/s²), \"10 mV/(m/s^2)\"")
    full_scale: str | None = Field(None, description="audio files: the quantity at digital "
                                   "full scale, e.g. \"10 V\"")
    sample_rate_hz: float | None = Field(None, gt=0, description="sample rate when the file "
                                         "states none (default: [measurement].sample_rate_hz)")
    pulses_per_rev: int | None = Field(None, ge=1, le=1_000_000,
                                       description="tacho (default 1) / encoder lines per rev")
    signal: Literal["analog", "pulse_times"] = Field(
        "analog", description="tacho/encoder: an analog pulse train, or pulse times [s]")
    threshold: float | None = Field(None, description="tacho/encoder edge level (file units; "
                                    "default: midway between the two state levels)")
    hysteresis: float | None = Field(None, ge=0, description="tacho/encoder hysteresis band "
                                     "(file units; default 10 % of the state-level difference)")

    @field_validator("sensitivity", "full_scale", "units", "file_units")
    @classmethod
    def _quantity(cls, v: str | None, info) -> str | None:  # noqa: ANN001
        if v is not None:
            parse_quantity(v if info.field_name in ("sensitivity", "full_scale") else f"1 {v}",
                           "a quantity with a unit" if info.field_name in
                           ("sensitivity", "full_scale") else "a unit")
        return v

    @model_validator(mode="after")
    def _check(self) -> MeasuredChannel:
        pulse = self.kind in ("tacho", "encoder")
        if pulse and self.shaft is None:
            raise ValueError(f"{self.kind} '{self.name}' needs shaft (the shaft measured)")
        if not pulse and (self.pulses_per_rev is not None or self.signal != "analog"
                          or self.threshold is not None or self.hysteresis is not None):
            raise ValueError(f"{self.kind} '{self.name}': pulses_per_rev/signal/threshold/"
                             "hysteresis are for tacho and encoder channels")
        if self.kind == "accelerometer" and self.location is None:
            raise ValueError(f"accelerometer '{self.name}' needs location ('ring' or a bearing "
                             "name, as in [[sensors]])")
        if self.sensitivity is not None:
            q = parse_quantity(self.sensitivity, "a sensitivity")
            if float(q.magnitude) <= 0:
                raise ValueError(f"sensitivity must be > 0, got {self.sensitivity!r}")
        return self

    @property
    def ppr(self) -> int:
        """Pulses per revolution (tacho default 1)."""
        return self.pulses_per_rev or 1

    @property
    def file_channel(self) -> str | int:
        return self.name if self.source is None else self.source


class MeasurementSpec(_M):
    """``[measurement]``: how the files of a measured record map onto the model."""

    channels: list[MeasuredChannel] = Field(min_length=1, description="[[measurement.channels]]")
    sample_rate_hz: float | None = Field(None, gt=0, description="sample rate of every channel "
                                         "when the file states none")
    speed_shaft: str | None = Field(None, description="the shaft speed_rpm/profile_rpm refer "
                                    "to (default: the config's first input link)")
    speed_rpm: float | None = Field(None, gt=0, description="operating speed of speed_shaft; "
                                    "the speed reference when no tacho, encoder or profile "
                                    "is given, else checked against it (2 %)")
    profile_rpm: list[tuple[float, float]] | None = Field(
        None, min_length=2, description="speed of speed_shaft against time, [[t_s, rpm], …] "
        "(piecewise linear; must cover the record)")
    load_nm: float | None = Field(None, description="operating load torque (N·m), recorded")
    timestamp: dt.datetime | str | None = Field(
        None, description="start of the record (default: from the file, else its name or "
        "modification time)")
    time_channel: str | None = Field(None, description="name of the file's time channel "
                                     "(default: detected: time, t, Time [s]…)")
    delimiter: str | None = Field(None, min_length=1, max_length=1,
                                  description="text tables: delimiter (default: detected)")
    decimal: Literal[".", ","] | None = Field(None, description="text tables: decimal mark "
                                              "(default: detected)")
    header: bool | None = Field(None, description="text tables: first line is a header "
                                "(default: detected)")
    min_revolutions: float = Field(2.0, gt=0, description="a record shorter than this many "
                                   "revolutions of the speed shaft is refused (default 2: the "
                                   "fewest for which a synchronous average differs from the "
                                   "signal itself)")

    @field_validator("profile_rpm")
    @classmethod
    def _profile(cls, v: list[tuple[float, float]] | None) -> list[tuple[float, float]] | None:
        if v is None:
            return v
        t = [p[0] for p in v]
        if any(b <= a for a, b in zip(t, t[1:], strict=False)):
            raise ValueError("times must increase strictly")
        if any(p[1] <= 0 for p in v):
            raise ValueError("speeds must be > 0 rpm (a shaft that stops cannot be order-"
                             "tracked)")
        return v

    @field_validator("timestamp")
    @classmethod
    def _stamp(cls, v: dt.datetime | str | None) -> dt.datetime | str | None:
        if isinstance(v, str):
            try:
                dt.datetime.fromisoformat(v)
            except ValueError:
                raise ValueError(f"{v!r} is not an ISO 8601 date-time (e.g. "
                                 "2026-03-01T12:00:00)") from None
        return v

    @model_validator(mode="after")
    def _check(self) -> MeasurementSpec:
        names = [c.name for c in self.channels]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"channels: duplicate channel names {dup}")
        if any(c.kind in ("tacho", "encoder") for c in self.channels) and \
                self.profile_rpm is not None:
            raise ValueError("profile_rpm: give the speed by a tacho/encoder channel or by "
                             "profile_rpm, not both")
        return self


def check_measurement(cfg: object) -> list[str]:
    """Cross-checks against the model: shafts and locations by the names ``[[sensors]]`` uses
    (:func:`geardyn.config.sensors.model_names`), stages that exist."""
    from geardyn.config.sensors import model_names

    spec: MeasurementSpec | None = getattr(cfg, "measurement", None)
    if spec is None:
        return []
    shafts, locations = model_names(cfg)
    links = {lk.name for lk in getattr(cfg, "links", [])}
    stages = {s.name for s in getattr(cfg, "planetary", [])}
    problems: list[str] = []
    if spec.speed_shaft is not None and spec.speed_shaft not in links:
        problems.append(f"measurement.speed_shaft: '{spec.speed_shaft}' is not a link of the "
                        f"mechanism (links: {', '.join(sorted(links))})")
    for i, c in enumerate(spec.channels):
        where = f"measurement.channels[{i}] '{c.name}'"
        known = (shafts or set()) | links
        if c.shaft is not None and c.shaft not in known:
            problems.append(f"{where}.shaft: '{c.shaft}' is not a shaft of the model (shafts: "
                            f"{', '.join(sorted(known))})")
        if locations is not None and c.location is not None and c.location not in locations:
            problems.append(f"{where}.location: unknown location '{c.location}' (locations: "
                            f"{', '.join(sorted(locations))})")
        if c.stage is not None and c.stage not in stages:
            problems.append(f"{where}.stage: unknown planetary stage '{c.stage}' (stages: "
                            f"{', '.join(sorted(stages)) or 'none'})")
        if c.location == "ring" and c.stage is None and len(stages) != 1:
            problems.append(f"{where}.stage: name the planetary stage of the ring sensor "
                            f"(stages: {', '.join(sorted(stages)) or 'none'})")
    return problems
