"""Every indicator a diagnosis writes has an explanation (definition, unit, reference).

The names are taken from what the code produces, not from a list: the features of short
simulated runs of the two diagnosis examples (seed 004 planetary with its ring accelerometer;
seed 002 FE transmission with the output-bearing accelerometer, transmission errors and
bearings), their reference residuals, the verdict with its isolation evidence (seed 002,
two baselines), and the single-TSA indicator sets of :mod:`geardyn.signal.indicators`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import geardyn
from geardyn.diagnosis.components import BEARING_LINES
from geardyn.diagnosis.explain import INDICATORS, Indicator, explain, indicators_markdown
from geardyn.diagnosis.faults import healthy_variant
from geardyn.diagnosis.features import features_from_result, with_reference_residuals
from geardyn.diagnosis.isolation import isolation_blocks
from geardyn.diagnosis.pipeline import judge_features, options
from geardyn.run import run_simulation
from geardyn.signal.indicators import gear_indicators, signal_indicators
from tests.conftest import EXAMPLES

DOCS = Path(__file__).resolve().parents[2] / "docs" / "indicators.md"


def _runs(path: Path, seeds: tuple[int, ...], **length):
    """(config, options, [(result, features)] per seed) of short runs of an example."""
    cfg = geardyn.load_config(path)
    opts = options(cfg)
    runs = []
    for s in seeds:
        ds = run_simulation(healthy_variant(cfg) if s else cfg, seed=s, **length)
        assert ds.attrs["status"] == "ok"
        runs.append((ds, features_from_result(ds, cfg, opts.channel, reference=opts.reference,
                                              skip_s=opts.skip_s, n_blocks=opts.blocks)))
    return cfg, opts, runs


@pytest.fixture(scope="module")
def seed002():
    """Seed 002 spall example, 4 output revolutions (≈ 1 s of simulation per run): the
    faulty record (seed 0) and two healthy baselines (seeds 1, 2)."""
    return _runs(EXAMPLES / "seed002_diagnose_spall.toml", (0, 1, 2), revolutions=4.0)


@pytest.fixture(scope="module")
def seed004():
    """Seed 004 sun-crack example, 4 s (about 2 sun revolutions after the skipped start)."""
    return _runs(EXAMPLES / "seed004_diagnose_sun_crack.toml", (0,), t_end_s=4.0)


def _missing(names) -> list[str]:
    return sorted({str(n) for n in names if explain(str(n)) is None})


def test_every_feature_of_a_real_run_is_explained(seed002, seed004) -> None:
    names = set()
    for _, _, runs in (seed002, seed004):
        for _, f in runs:
            names |= set(f.table["indicator"])
    # the run produced the families the brief names (gear, wheel, bearing indicators)
    assert {"FM0", "FM4", "NA4", "NB4", "ER", "diff_rms", "diff_kurtosis", "SER",
            "sideband_kurtosis", *BEARING_LINES} <= names
    assert _missing(names) == []


def test_reference_residuals_are_explained(seed002) -> None:
    _, _, runs = seed002
    base, rec = with_reference_residuals([f for _, f in runs[1:]], runs[0][1])
    names = set(rec.table["indicator"]) | {n for b in base for n in b.table["indicator"]}
    assert {"RR_kurtosis", "RR_rms"} <= names
    assert _missing(names) == []


def test_every_indicator_of_a_verdict_is_explained(seed002) -> None:
    """The verdict's keys: detection indicators and the isolation evidence the pipeline adds
    (whatever its current names), in the multi-channel ``channel:indicator`` form too."""
    cfg, opts, runs = seed002
    blocks = [isolation_blocks(ds, cfg, opts.channel, reference=opts.reference,
                               skip_s=opts.skip_s) for ds, _ in runs]
    verdict = judge_features(cfg, opts, [f for _, f in runs[1:]], runs[0][1],
                             baseline_blocks=blocks[1:], record_blocks=blocks[0])
    keys = [k for c in verdict.components.values() for k in c.indicators]
    assert keys
    assert _missing(keys) == []
    assert _missing(f"acc_output:{k}" for k in keys) == []


def test_single_tsa_indicator_sets_are_explained() -> None:
    th = np.arange(256) * 2 * np.pi / 256
    x = np.sin(19 * th) + 0.1 * np.sin(3 * th) + 0.01 * np.cos(7 * th)
    names = set(gear_indicators(x, 19)) | set(signal_indicators(x))
    assert {"M6A", "M8A", "SLF", "crest_factor", "skewness", "peak", "rms"} <= names
    assert _missing(names) == []


def test_lookup_forms() -> None:
    fm4 = explain("FM4")
    assert isinstance(fm4, Indicator) and fm4.name == "FM4"
    assert explain("ring_acc:FM4") is fm4
    assert explain("rms") is INDICATORS["RMS"]
    for line in BEARING_LINES:
        for suffix in ("concentration", "band energy"):
            ind = explain(f"acc:{line} {suffix}")
            assert ind is not None and ind.name == f"{line} {suffix}"
            assert line in ind.definition or "ball" in ind.definition or "cage" in ind.definition
    # a line name the registry does not know still gets the pattern's explanation
    other = explain("XYZ band energy")
    assert other is not None and "XYZ" in other.definition
    assert explain("not an indicator") is None
    assert explain("SDR").higher_is_worse and not explain("skewness").higher_is_worse


def test_entries_are_complete() -> None:
    for key, ind in INDICATORS.items():
        assert ind.definition.strip().endswith((".", ")")), key
        assert ind.unit in ("1", "channel units"), key
        assert ind.reference.strip(), key
        # every reference names a year (author year) or says it is a geardyn measure
        assert any(ch.isdigit() for ch in ind.reference) or "geardyn" in ind.reference, key
    assert INDICATORS["diff_rms"].unit == "channel units"
    assert INDICATORS["FM4"].unit == "1"


def test_docs_table_is_the_generated_text() -> None:
    """Pin: docs/indicators.md is the text indicators_markdown() writes (regenerate with
    ``python -c "from geardyn.diagnosis.explain import indicators_markdown as m;
    open('docs/indicators.md', 'w').write(m())"``)."""
    assert DOCS.read_text(encoding="utf-8") == indicators_markdown()
    # one row per distinct entry (aliases share their entry)
    rows = [ln for ln in indicators_markdown().splitlines() if ln.startswith("| ")][1:]
    assert len(rows) == len({id(v) for v in INDICATORS.values()})
