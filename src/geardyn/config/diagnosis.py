"""Config schema of the diagnosis (``geardyn diagnose``): the optional ``[diagnosis]`` section.

It states how the healthy baseline is built (simulation seeds), which record is judged (its
seed), which sensor channel is analysed and the threshold rule (μ + k·σ per component and
indicator, σ floored at ``sigma_floor``·|μ|; see docs/diagnosis.md). Command-line options
override these values. SI units, stated in the field names.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, field_validator


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
        default_factory=lambda: [0, 1, 2], min_length=1,
        description="simulation seeds of the healthy baseline runs",
    )
    record_seed: int = Field(100, ge=0, description="simulation seed of the judged (faulty) run")
    threshold_k: float = Field(3.0, gt=0, description="threshold = mean + k·std of the baseline")
    sigma_floor: float = Field(
        0.05, ge=0, lt=1,
        description="std floored at this fraction of |mean| (deterministic baselines)",
    )
    blocks: int = Field(4, ge=1, le=64, description="blocks of whole revolutions per record")
    skip_s: float = Field(0.0, ge=0, description="start transient discarded (s)")
    t_end_s: float | None = Field(
        None, gt=0, description="planetary model: simulated duration override (s)")
    revolutions: float | None = Field(
        None, gt=0, description="FE transmission: revolutions of the speed-law reference "
        "(overrides the speed law's)")
    reference_residuals: bool = Field(
        False, description="add the reference-residual indicators RR_kurtosis/RR_rms (each "
        "block's TSA minus the healthy baselines' mean TSA; needs ≥ 2 baseline records)",
    )

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
