"""Config schema of the diagnosis (``geardyn diagnose``): the optional ``[diagnosis]`` section.

It states how the healthy baseline is built (simulation seeds and the ensemble over what is
uncertain in a real fleet, ``[diagnosis.ensemble]``: :class:`EnsembleSpec`,
docs/diagnosis_ensemble.md), which record is judged (its seed), which sensor channel is analysed,
the threshold rule (μ + k·σ per component and indicator, σ floored at ``sigma_floor``·|μ|; see
docs/diagnosis.md), the false-alarm probability and the localisation confidence. Command-line
options override these values. SI units, stated in the field names.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

#: Dynamic runs of the default baseline ensemble (see :class:`EnsembleSpec`).
DEFAULT_MEMBERS = 6


class EnsembleSpec(BaseModel):
    """``[diagnosis.ensemble]``: the healthy baseline as an ensemble over what is uncertain.

    A fleet's healthy records differ by far more than sensor noise: each machine runs at its
    own speed and load within the acquisition window, carries its own manufacturing errors and
    its own sensor mounting. Each of the ``members`` dynamic runs draws a speed factor, a load
    factor and manufacturing errors; each run is measured ``measurements_per_run`` times, each
    measurement with its own transfer path, sensitivity and noise (the sensors act after the
    dynamics, so one run serves several measurements). Every draw is uniform on
    ``nominal × (1 ± tolerance)`` (``± pin_error_m`` for the planet pins): a tolerance states a
    range, not a standard deviation, and the uniform is the distribution of largest entropy on
    a range (Jaynes 1957). Draws come from ``numpy.random.default_rng([seed, member seed, …])``:
    the same config and seeds give the same members, and adding members keeps the earlier ones.
    Tolerance 0 switches a perturbation off. docs/diagnosis_ensemble.md gives the defaults and
    why.
    """

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    members: int = Field(
        DEFAULT_MEMBERS, ge=1, le=64,
        description="dynamic runs of the healthy baseline (their seeds are "
        "diagnosis.baseline_seeds when given, else 0 … members − 1). Default 6: with 2 "
        "measurements each and the default 2 blocks of the Wang 2010 example, 24 pooled samples "
        "per indicator, where the small-sample factor of the threshold rule is ≈ 1.14 (1.34 at "
        "12); chosen so that `geardyn diagnose` of the Wang 2010 example stays under 60 s on one "
        "core (a judgement of cost against spread)")
    measurements_per_run: int = Field(
        2, ge=1, le=16,
        description="sensor variants (transfer path, sensitivity, noise) measured on each "
        "dynamic run; the sensors act after the dynamics, so a measurement costs ≈ 0.1 s "
        "against ≈ 3 s for a run of the Wang 2010 example. Default 2: doubles the samples of "
        "the sensor-side spread at no dynamic cost (judgement)")
    seed: int = Field(0, ge=0, description="seed of the perturbation draws (the run seeds "
                      "drive the noise and the Wang 2010 random impulse errors)")
    speed_tolerance: float = Field(
        0.02, ge=0, le=0.5,
        description="relative ± of every stated input speed (uniform). Default 2 %: an "
        "induction motor on the mains runs between no-load and rated slip (5 % for the Wang "
        "2010 motor, 950 of 1000 rpm) and its supply frequency may stray ±1 % (EN 50160, 50 Hz "
        "± 1 % during 99.5 % of a year); HUMS acquisitions are gated on a speed window of a few "
        "per cent (judgement)")
    load_tolerance: float = Field(
        0.1, ge=0, le=0.5,
        description="relative ± of every stated load torque (uniform). Default 10 %: records "
        "accepted within a torque window of the nominal regime (judgement; HUMS acquire at "
        "stated regimes, not at one torque)")
    error_scale_tolerance: float = Field(
        0.5, ge=0, le=1,
        description="relative ± of the configured manufacturing-error amplitudes (uniform, "
        "one factor per run): Wang 2010 random impulse errors random_error_max_m, configured "
        "planet pin errors pin_errors_m, FE unbalances mass_eccentricity_kg_m. Default 50 %: a "
        "gear of a given ISO 1328-1 accuracy class has errors anywhere below its tolerance, "
        "and adjacent classes differ by √2 (ISO 1328-1:2013 §5.2); judgement")
    pin_error_m: float = Field(
        10e-6, ge=0, le=1e-3,
        description="± tangential planet pin position error (m, uniform, independent per "
        "planet; added to any configured pin_errors_m; planetary stages). Default 10 µm: a "
        "carrier bored to the accuracy of its gears; ISO 1328-1 single pitch tolerance of the "
        "Wang 2010 sun (m_n ≈ 16 mm, d ≈ 304 mm) is ≈ 11 µm in class 5 and ≈ 15 µm in class 6 "
        "(ISO 1328-1:1995 f_pt = 0.3(m_n + 0.4√d) + 4 µm × 2^((Q−5)/2)); judgement")
    bearing_clearance_tolerance: float = Field(
        0.3, ge=0, lt=1,
        description="relative ± of each FE-transmission bearing's diametral_clearance_m "
        "(uniform, independent per bearing). Default 30 %: ISO 5753-1 radial internal "
        "clearance groups span about ±50 % of their middle (e.g. 6–20 µm, normal group, "
        "deep-groove ball bearings of 30–40 mm bore); fits narrow the mounted spread "
        "(judgement)")
    transfer_path_tolerance: float = Field(
        0.1, ge=0, le=0.5,
        description="relative ± of each accelerometer transfer-path mode's frequency and "
        "damping ratio (uniform, independent per mode, per measurement). Default 10 %: the "
        "housing modes of nominally identical machines and mountings differ by several per "
        "cent in frequency and tens of per cent in damping (bolt preloads, temperature, "
        "mounting: ISO 5348); judgement")
    sensitivity_tolerance: float = Field(
        0.05, ge=0, le=0.5,
        description="relative ± of each accelerometer's gain (uniform, per measurement; "
        "applied to the transfer path, 1/modal_mass_kg). Default 5 %: the usual sensitivity "
        "tolerance of a calibrated piezoelectric accelerometer (manufacturers' data sheets, "
        "±5 %; ±10 % uncalibrated)")
    noise_tolerance: float = Field(
        0.5, ge=0, le=1,
        description="relative ± of each accelerometer's noise_rms (uniform, per "
        "measurement). Default 50 %: background vibration from neighbouring machines, cabling "
        "and electrical noise vary from site to site by factors, not per cents (judgement)")


class DiagnosisSpec(BaseModel):
    """``[diagnosis]``: baseline, record and threshold settings of ``geardyn diagnose``."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    channel: str | None = Field(
        None, description="sensor channel analysed (name of a [[sensors]] entry); default: first"
    )
    reference: str | None = Field(
        None, description="link whose angle is the order reference; default: the channel's shaft"
    )
    baseline_seeds: list[int] = Field(
        default_factory=lambda: list(range(DEFAULT_MEMBERS)), min_length=1,
        description="simulation seeds of the healthy baseline runs (the ensemble members); "
        "default 0 … ensemble.members − 1. When given, they fix the members: ensemble.members "
        "is set to their number",
    )
    record_seed: int = Field(100, ge=0, description="simulation seed of the judged (faulty) run")
    threshold_k: float | None = Field(
        None, gt=0, description="fixed threshold factor (mean + k·σ per indicator); default: "
        "from false_alarm_probability, k = Φ⁻¹(1 − α) with the Šidák level α over all tests")
    sigma_floor: float = Field(
        0.05, ge=0, lt=1,
        description="std floored at this fraction of |mean| (deterministic baselines)",
    )
    family_floor: bool = Field(
        True, description="raise each log-scale spread to the median spread of the same "
        "indicator (isolation statistic) over the machine's components (not bearings), "
        "never lowering one (borrowing strength across tests, after Smyth 2004; "
        "docs/diagnosis.md); false: each test on its own runs only",
    )
    blocks: int = Field(4, ge=1, le=64, description="blocks of whole revolutions per record")
    skip_s: float = Field(0.0, ge=0, description="start transient discarded (s)")
    t_end_s: float | None = Field(
        None, gt=0, description="planetary model: simulated duration override (s)")
    revolutions: float | None = Field(
        None, gt=0, description="FE transmission: revolutions of the speed-law reference "
        "(overrides the speed law's)")
    false_alarm_probability: float = Field(
        0.01, gt=0, le=0.2,
        description="probability that a healthy record is reported detected (machine level): "
        "the thresholds are set at this level over all components and indicators")
    localisation_confidence: float = Field(
        0.95, ge=0.5, lt=1,
        description="posterior probability a component needs to be named as the location; "
        "below it the verdict lists candidates (detected, location uncertain)")
    ensemble: EnsembleSpec = Field(
        default_factory=EnsembleSpec,
        description="[diagnosis.ensemble]: what varies between the healthy baseline members")
    reference_residuals: bool = Field(
        False, description="add the reference-residual indicators RR_kurtosis/RR_rms (each "
        "block's TSA minus the healthy baselines' mean TSA; needs ≥ 2 baseline records)",
    )

    @model_validator(mode="before")
    @classmethod
    def _member_seeds(cls, data: Any) -> Any:
        """baseline_seeds default to 0 … ensemble.members − 1; given, they set the members."""
        if not isinstance(data, dict):
            return data
        ens = data.get("ensemble")
        if isinstance(ens, EnsembleSpec):
            ens = ens.model_dump()
        seeds = data.get("baseline_seeds")
        n = ens.get("members", DEFAULT_MEMBERS) if isinstance(ens, dict) else DEFAULT_MEMBERS
        valid = isinstance(n, int) and not isinstance(n, bool) and 1 <= n <= 64
        if not valid:  # refused by EnsembleSpec, naming ensemble.members
            return {k: v for k, v in data.items() if k != "baseline_seeds" or v is not None}
        if seeds is None:
            return {**data, "baseline_seeds": list(range(n))}
        if isinstance(seeds, list | tuple) and seeds and (ens is None or isinstance(ens, dict)):
            return {**data, "ensemble": {**(ens or {}), "members": len(seeds)}}
        return data

    @field_validator("baseline_seeds")
    @classmethod
    def _distinct(cls, seeds: list[int]) -> list[int]:
        if any(s < 0 for s in seeds):
            raise ValueError(f"seeds must be >= 0, got {seeds}")
        if len(set(seeds)) != len(seeds):
            raise ValueError(f"seeds must be distinct, got {seeds}")
        return seeds


def check_diagnosis(cfg: object) -> list[str]:
    """Cross-checks: the channel is a [[sensors]] entry that records a signal (not a tacho),
    the reference a mechanism link, skip_s shorter than t_end_s."""
    spec: DiagnosisSpec | None = getattr(cfg, "diagnosis", None)
    if spec is None:
        return []
    problems: list[str] = []
    sensors = {s.name: s for s in getattr(cfg, "sensors", [])}
    meas = getattr(cfg, "measurement", None)  # measured channels (geardyn.config.measurement)
    if meas is not None:
        sensors.update({c.name: c for c in meas.channels if c.name not in sensors})
    if spec.channel is not None:
        usable = [n for n, s in sensors.items() if s.kind != "tacho"]
        if spec.channel not in sensors:
            problems.append(f"diagnosis.channel: unknown sensor '{spec.channel}' (sensors: "
                            f"{', '.join(usable) or 'none: add [[sensors]]'})")
        elif sensors[spec.channel].kind == "tacho":
            problems.append(f"diagnosis.channel: '{spec.channel}' is a tacho (a speed "
                            f"reference, not a signal); choose one of: {', '.join(usable)}")
    links = {lk.name for lk in getattr(cfg, "links", [])}
    if spec.reference is not None and links and spec.reference not in links:
        problems.append(f"diagnosis.reference: unknown link '{spec.reference}' (links: "
                        f"{', '.join(sorted(links))})")
    if spec.t_end_s is not None and spec.skip_s >= spec.t_end_s:
        problems.append(f"diagnosis.skip_s: the discarded start {spec.skip_s:g} s must be "
                        f"shorter than t_end_s {spec.t_end_s:g} s")
    return problems
