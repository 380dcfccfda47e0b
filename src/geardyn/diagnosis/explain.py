"""What each condition indicator and isolation measure means: definition, unit, source.

:data:`INDICATORS` holds one :class:`Indicator` per name that
:mod:`geardyn.diagnosis.features` (detection indicators per block), the reference residuals
(:func:`geardyn.diagnosis.features.reference_residuals`), :mod:`geardyn.diagnosis.isolation`
(isolation evidence) and :mod:`geardyn.signal.indicators` write into a verdict, plus the
patterns ``'<LINE> concentration'`` and ``'<LINE> band energy'`` (``LINE`` a bearing line,
:data:`geardyn.diagnosis.components.BEARING_LINES`). :func:`explain` looks a name up, also in
the ``'channel:indicator'`` form a verdict uses when several channels are judged.
:func:`indicators_markdown` writes the table of ``docs/indicators.md`` (a test keeps the two
equal).

Signals named in the definitions (Zakrajsek, Townsend & Decker 1993, NASA TM-105950;
Lebold et al. 2000, "Review of vibration analysis methods for gearbox diagnostics and
prognostics", 54th MFPT): the **TSA** is the time-synchronous average of whole revolutions of
the component's own angle; its **regular** part is the mesh harmonics (of every wheel on the
component, and other regular orders such as a ring's planet-pass orders); the **residual** is
the TSA without the mean, the shaft order and the regular part; the **difference** signal is
the residual without the first-order sidebands of the mesh harmonics.

References are given as author year (and equation where the source numbers it and geardyn
follows it); where a geardyn measure has no published counterpart the reference names the
published idea it rests on and says so.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from geardyn.diagnosis.components import BEARING_LINES

__all__ = ["INDICATORS", "Indicator", "explain", "indicators_markdown"]


@dataclass(frozen=True)
class Indicator:
    """Explanation of one indicator: ``definition`` (one or two sentences), ``unit`` ("1" for
    a dimensionless ratio, "channel units" for a level in the analysed channel's unit),
    ``reference`` (author year, equation) and ``higher_is_worse`` (False for an indicator
    judged on both sides of its baseline, e.g. skewness)."""

    name: str
    definition: str
    unit: str
    reference: str
    higher_is_worse: bool = True


_ZTD = "Zakrajsek, Townsend & Decker 1993 (NASA TM-105950)"
_STEWART = "Stewart 1977; formula as in " + _ZTD
_SEED003 = "Hammami 2015"

_LIST: tuple[Indicator, ...] = (
    # ---------------------------------------------------------------- TSA statistics
    Indicator("FM0", "Peak-to-peak of the component's TSA divided by the sum of the amplitudes "
              "of its mesh harmonics (and other regular orders). Rises with heavy wear or a "
              "broken tooth that changes the peak-to-peak more than the meshing.", "1",
              _STEWART),
    Indicator("FM4", "Normalised kurtosis N·Σd⁴/(Σd²)² of the difference signal d: about 3 "
              "when d is Gaussian noise, larger when one or a few teeth add a local impulse "
              "(crack, spall).", "1", _STEWART),
    Indicator("M6A", "Normalised sixth moment N²·Σd⁶/(Σd²)³ of the difference signal (≈ 15 "
              "for Gaussian noise); more sensitive to isolated peaks than FM4.", "1",
              "Martin 1989; formula as in " + _ZTD),
    Indicator("M8A", "Normalised eighth moment N³·Σd⁸/(Σd²)⁴ of the difference signal (≈ 105 "
              "for Gaussian noise).", "1", "Martin 1989; formula as in " + _ZTD),
    Indicator("NA4", "Kurtosis of the residual signal of the current block normalised by the "
              "mean variance of the residuals of the blocks so far: a trend indicator that "
              "keeps rising as damage spreads over several teeth (FM4 falls back to 3).", "1",
              _ZTD),
    Indicator("NB4", "NA4 applied to the envelope (Hilbert magnitude) of the TSA band-passed "
              "around the mesh harmonics: detects the load fluctuation of a damaged tooth. "
              "On a wheel sharing its shaft: the wheel's own mesh harmonics and "
              "unambiguous sidebands only.", "1",
              "Zakrajsek, Handschuh & Decker 1994 (spiral bevel gear fatigue data, NASA TM)"),
    Indicator("ER", "Energy ratio RMS(difference)/RMS(regular): the share of the synchronous "
              "vibration not explained by regular meshing; rises with wear spread over many "
              "teeth. Computed from unbiased synchronous powers so that non-synchronous "
              "content left in a short average does not raise it.", "1",
              "Swansson 1980; " + _ZTD + "; unbiased powers after Braun 1975"),
    Indicator("energy_ratio", "Energy ratio RMS(difference)/RMS(regular) of one TSA (plain "
              "form of ER).", "1", "Swansson 1980; " + _ZTD),
    Indicator("diff_rms", "RMS of the difference signal (unbiased synchronous power): the "
              "level of everything synchronous with the component that is not regular "
              "meshing.", "channel units", _ZTD + "; unbiased powers after Braun 1975"),
    Indicator("diff_kurtosis", "Normalised kurtosis of the difference signal (3 for Gaussian "
              "noise); the same as FM4 where the component has meshes, and defined also where "
              "it has none (mean and shaft order removed only).", "1", _STEWART),
    Indicator("SLF", "Sideband level factor: amplitudes of the first sidebands of the mesh "
              "fundamental (orders Z ± 1) over the RMS of the TSA; rises with shaft "
              "misalignment, eccentricity or a cracked tooth modulating the mesh.", "1",
              "Swansson 1980; formula as in Lebold et al. 2000"),
    Indicator("SER", "Sideband energy ratio of one wheel: sum of the amplitudes of its mesh "
              "sidebands (up to 3 per side, those not shared with another wheel of the shaft) "
              "over the sum of its mesh-harmonic amplitudes.", "1", "Hanna et al. 2011"),
    Indicator("sideband_kurtosis", "Normalised kurtosis (FM4 form) of the signal rebuilt from "
              "one wheel's unambiguous mesh sidebands only: ≈ 2.25 for a once-per-revolution "
              "sinusoidal modulation, large for a local tooth fault (geardyn measure).", "1",
              "geardyn; FM4 form of " + _ZTD + " on the sidebands of Hanna et al. 2011"),
    # ---------------------------------------------------------------- plain statistics
    Indicator("RMS", "Root mean square of the signal (Hammami 2015, eq. 1.21): its overall level.",
              "channel units", _SEED003 + ", eq. 1.21"),
    Indicator("peak", "Largest absolute value of the signal.", "channel units",
              _SEED003 + ", §4.1.2"),
    Indicator("crest factor", "Peak over RMS (√2 for a sine): rises with impulses such as "
              "those of a broken tooth.", "1", _SEED003 + ", eq. 1.22"),
    Indicator("kurtosis", "Normalised fourth central moment of the signal (3 for Gaussian, "
              "1.5 for a sine): rises with impulsive content.", "1", _SEED003 + ", eq. 1.24"),
    Indicator("skewness", "Normalised third central moment (0 for a symmetric distribution); "
              "judged on both sides of the baseline, its sign follows the sensor "
              "direction.", "1", "Lebold et al. 2000", higher_is_worse=False),
    # ---------------------------------------------------------------- bearings
    *(Indicator(line, f"{name} line ratio: mean over harmonics 1–3 of the peak of the "
                "squared-envelope spectrum within ±max(2 bins, 2 %) of the line over the "
                "median level within ±max(20 bins, 20 %); ≈ 1 without a line, large for a "
                f"{what}.", "1",
                "Randall & Antoni 2011 (squared-envelope spectrum; band from the "
                "kurtogram, Antoni 2007)")
      for line, name, what in (
          ("BPFO", "Ball-pass frequency, outer race", "localised outer-race defect"),
          ("BPFI", "Ball-pass frequency, inner race", "localised inner-race defect"),
          ("BSF", "Ball (roller) spin frequency", "rolling-element defect"),
          ("FTF", "Fundamental train (cage) frequency", "cage defect or cage modulation"))),
    # ---------------------------------------------------------------- reference residuals
    Indicator("RR_kurtosis", "Kurtosis of the reference residual: each block's TSA minus the "
              "healthy baselines' mean TSA of the same component (3 for Gaussian noise). "
              "Detects that the machine changed, not where.", "1",
              "Wang & Wong 2002 (reference residual, healthy average as reference)"),
    Indicator("RR_rms", "RMS of the reference residual over the RMS of the healthy reference "
              "TSA (mean removed): the fraction of the component's synchronous vibration that "
              "changed.", "1", "Wang & Wong 2002; baseline normalisation as in Decker 2002 "
              "(NASA TM-2002-211491)"),
    # ---------------------------------------------------------------- isolation evidence
    Indicator("SDR", "Synchronous deviation ratio: F statistic of a one-way analysis of "
              "variance of the component's revolutions, ‖mean deviation‖² over its standard "
              "error, the deviation being each revolution's difference signal minus the "
              "healthy baseline's. ≈ 1 when nothing synchronous with the component changed.",
              "1", "Braun 1975; McFadden 1987 (synchronous averaging as an F test)"),
    Indicator("SDR_TE", "SDR computed on the transmission error of the wheel's own mesh "
              "(encoder pair) instead of the housing accelerometer: tells apart wheels that "
              "share a shaft.", "1", "Braun 1975; McFadden 1987"),
    Indicator("cSDR", "Coherent synchronous deviation ratio: per order of the component, "
              "the F statistic |record mean − baseline mean|² over its standard error (pooled "
              "revolution-to-revolution variance), averaged over the component's orders. A "
              "fault that repeats every revolution raises many orders at once; ≈ 1 when "
              "nothing synchronous with the component changed.", "1",
              "McFadden 1987; Braun 1975 (one-way analysis of variance of the revolutions)"),
    Indicator("cSDR_TE", "cSDR on the transmission error of the wheel's own mesh (encoder "
              "pair), which tells apart wheels sharing a shaft.", "1",
              "McFadden 1987; Braun 1975"),
    Indicator("cSDR_planet", "cSDR on the planet-separated signal (McFadden's planet windows "
              "at the ring sensor): the planet whose revolutions deviate coherently.", "1",
              "McFadden 1994 (planet separation); McFadden 1987; Braun 1975"),
)

#: Explanation per indicator name (detection indicators and isolation evidence).
INDICATORS: dict[str, Indicator] = {i.name: i for i in _LIST}

# Spellings of the same quantities written by geardyn.signal.indicators
for _alias, _name in (("rms", "RMS"), ("crest_factor", "crest factor")):
    INDICATORS[_alias] = INDICATORS[_name]

_LINE_NAMES = {
    "BPFO": "outer-race ball-pass", "BPFI": "inner-race ball-pass",
    "BSF": "ball-spin", "FTF": "cage (fundamental train)",
}
_PATTERNS: dict[str, tuple[str, str, str]] = {
    "concentration": (
        "Line-family concentration of the {what} line: the share of the increase of the "
        "squared-envelope spectrum over the baseline found on every harmonic of the line "
        "(±1 bin), divided by the share of bins that comb covers (≈ 1 for an increase "
        "spread evenly, large when the increase sits on this bearing's own comb).",
        "1",
        "geardyn measure; the comb read of Randall & Antoni 2011",
    ),
    "band energy": (
        "Fault-band energy share of the {what} line: energy ΣS² of the squared-envelope "
        "spectrum in ±1-bin bands on every harmonic of the line over its energy in the whole "
        "band (a sensor or transfer-path gain cancels); judged against the same share in "
        "each healthy baseline member.",
        "1",
        "MathWorks Predictive Maintenance Toolbox, faultBandMetrics (band power); "
        "Randall & Antoni 2011",
    ),
}
for _line in BEARING_LINES:
    for _suffix, (_text, _unit, _ref) in _PATTERNS.items():
        _key = f"{_line} {_suffix}"
        INDICATORS[_key] = Indicator(_key, _text.format(what=_LINE_NAMES[_line]), _unit, _ref)

_PATTERN = re.compile(r"^(?P<line>\S+) (?P<suffix>concentration|band energy)$")


def explain(name: str) -> Indicator | None:
    """Explanation of an indicator name as it appears in a verdict (``'FM4'``,
    ``'acc:FM4'``, ``'BPFO concentration'``, ``'ring_acc:BPFI band energy'``), or None when
    no explanation is registered."""
    key = str(name).rpartition(":")[2].strip()
    if key in INDICATORS:
        return INDICATORS[key]
    m = _PATTERN.match(key)
    if m is None:
        return None
    line, suffix = m.group("line"), m.group("suffix")
    text, unit, ref = _PATTERNS[suffix]
    return Indicator(key, text.format(what=_LINE_NAMES.get(line, line)), unit, ref)


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def indicators_markdown() -> str:
    """The text of ``docs/indicators.md``: one table row per entry of :data:`INDICATORS`
    (aliases left out), in registration order."""
    lines = [
        "# Indicators",
        "",
        "Every condition indicator and isolation measure that `geardyn diagnose` writes into "
        "a verdict and its report. Generated from `geardyn.diagnosis.explain.INDICATORS` "
        "(`indicators_markdown()`); a test keeps this file equal to it. Unit `1`: "
        "dimensionless; `channel units`: the unit of the analysed channel. Direction "
        "`upper`: an alarm when the value rises above its baseline threshold; `two-sided`: "
        "when it leaves the baseline band on either side.",
        "",
        "| name | definition | unit | direction | reference |",
        "|---|---|---|---|---|",
    ]
    seen: set[int] = set()
    for ind in INDICATORS.values():
        if id(ind) in seen:
            continue
        seen.add(id(ind))
        direction = "upper" if ind.higher_is_worse else "two-sided"
        lines.append(f"| {_cell(ind.name)} | {_cell(ind.definition)} | {ind.unit} | "
                     f"{direction} | {_cell(ind.reference)} |")
    return "\n".join(lines) + "\n"
