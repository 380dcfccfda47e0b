"""report.html from synthetic features: one self-contained page that parses (balanced tags,
every image a PNG data URI) and holds the verdict, kinematic and indicator tables; the order
range drawn reaches the sensor's band (numbers by hand); the margin chart's worst indicator
is the table's; every indicator shown is explained; ``uncertain`` states and the
detection/localisation answers are rendered."""

from __future__ import annotations

import base64
import re
from dataclasses import replace
from html.parser import HTMLParser
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import geardyn
from geardyn.diagnosis.baseline import ThresholdRule, thresholds
from geardyn.diagnosis.explain import explain
from geardyn.diagnosis.faults import fault_list
from geardyn.diagnosis.report import (
    margin_figure,
    margin_rows,
    sensor_band,
    sensor_band_figure,
    spectrogram_segment,
    write_report,
)
from geardyn.diagnosis.verdict import judge
from geardyn.errors import InputError
from geardyn.kinematics import characteristic_frequencies
from geardyn.signal import order_spectrum, spectral_markers
from tests.conftest import EXAMPLES

VOID = {"meta", "img", "br", "hr", "input", "link", "col", "area", "base", "source", "wbr"}
PNG = b"\x89PNG\r\n\x1a\n"


class PageChecker(HTMLParser):
    """Balanced tags, images and the text of every table cell."""

    def __init__(self) -> None:
        super().__init__()
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.images: list[str] = []
        self.links: list[str] = []
        self.cells: list[tuple[str, str]] = []  # (class, text)
        self._cell: list | None = None

    def handle_starttag(self, tag: str, attrs: list) -> None:
        a = dict(attrs)
        if tag == "img":
            self.images.append(a.get("src", ""))
        for key in ("href", "src"):
            if key in a and tag != "img":
                self.links.append(a[key])
        if tag in ("td", "th"):
            self._cell = [a.get("class") or "", ""]
        if tag not in VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag: str) -> None:
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.stack[-1] if self.stack else None}>")
        else:
            self.stack.pop()
        if tag in ("td", "th") and self._cell is not None:
            self.cells.append((self._cell[0], self._cell[1].strip()))
            self._cell = None

    def handle_data(self, data: str) -> None:
        if self._cell is not None:
            self._cell[1] += data


def synthetic_features(freqs, fault: float, seed: int) -> SimpleNamespace:
    """Features of a 19-tooth sun with ``fault`` × an impact per revolution, 4 blocks."""
    rng = np.random.default_rng(seed)
    spr = 512
    th = np.arange(8 * spr) * 2 * np.pi / spr
    x = np.sin(19 * th) + 0.05 * rng.standard_normal(th.size)
    x += fault * np.exp(-(((th % (2 * np.pi)) - 1.0) ** 2) / 0.002)
    one = x.reshape(8, spr).mean(axis=0)
    tsa = xr.DataArray(one, coords={"angle": np.arange(spr) * 360.0 / spr}, dims="angle",
                       attrs={"units": "m/s²"})
    spec = order_spectrum(x, spr)
    spec.attrs["units"] = "m/s²"
    rows = []
    for b in range(4):
        for comp, kind in (("planetary.sun", "sun"), ("planetary.ring", "ring")):
            base = 3.0 + (6.0 * fault if comp == "planetary.sun" else 0.0)
            rows += [
                {"component": comp, "kind": kind, "indicator": "FM4",
                 "value": base + 0.05 * rng.standard_normal(), "block": b, "channel": "acc"},
                {"component": comp, "kind": kind, "indicator": "skewness",
                 "value": 0.01 * rng.standard_normal(), "block": b, "channel": "acc"},
            ]
    return SimpleNamespace(
        table=pd.DataFrame(rows), tsa={"planetary.sun": tsa, "planetary.ring": tsa * 0.5},
        order_spectrum=spec, envelope_spectrum=spec * 0.1, band=(100.0, 300.0), kurtogram=None,
        markers=spectral_markers(freqs),
    )


def synthetic_result(seconds: float = 4.0, fs: float = 2000.0) -> xr.Dataset:
    t = np.arange(int(seconds * fs)) / fs
    acc = np.sin(2 * np.pi * 8.36 * t) + 0.1 * np.sin(2 * np.pi * 16.7 * t)
    name = "sensors.acc"
    return xr.Dataset(
        {name: ((f"{name}.time",), acc, {"units": "m/s²", "sensor_kind": "accelerometer",
                                         "sampling": "time", "shaft": "sun",
                                         "sample_rate_hz": fs})},
        coords={f"{name}.time": ((f"{name}.time",), t, {"units": "s"})},
    )


def make_report(tmp_path: Path) -> tuple[Path, object]:
    cfg = geardyn.load_config(EXAMPLES / "planetary_reclaimer.toml")
    freqs = characteristic_frequencies(geardyn.analyze_kinematics(cfg),
                                       dict(cfg.input_speeds_rpm))
    healthy = [synthetic_features(freqs, 0.0, s) for s in range(3)]
    faulty = synthetic_features(freqs, 1.0, 100)
    rule = ThresholdRule()
    verdict = judge(faulty.table, thresholds([h.table for h in healthy], rule), rule,
                    machine=cfg.name, baseline={"seeds": [0, 1, 2]},
                    record_info={"seed": 100}, expected_faults=fault_list(cfg))
    path = write_report(tmp_path / "out", verdict, faulty, healthy=healthy[0], freqs=freqs,
                        record_ds=synthetic_result(), channel="acc")
    return path, verdict


def test_report_is_one_self_contained_page(tmp_path: Path) -> None:
    path, verdict = make_report(tmp_path)
    assert path == tmp_path / "out" / "report.html"
    assert [p.name for p in path.parent.iterdir()] == ["report.html"]
    text = path.read_text(encoding="utf-8")
    page = PageChecker()
    page.feed(text)
    page.close()
    assert page.errors == []
    assert page.stack == []  # every tag closed
    assert page.links == []  # no external stylesheet, script or link
    assert "<script" not in text
    # order spectrum, envelope, 2 TSA, spectrogram, CWT
    assert len(page.images) >= 6
    for src in page.images:
        assert src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1], validate=True).startswith(PNG)
    assert verdict.components["planetary.sun"].state == "alarm"
    assert verdict.components["planetary.ring"].state == "healthy"


def test_report_holds_the_verdict_kinematics_and_indicator_tables(tmp_path: Path) -> None:
    path, verdict = make_report(tmp_path)
    page = PageChecker()
    page.feed(path.read_text(encoding="utf-8"))
    texts = [t for _, t in page.cells]
    # verdict table: one state cell per component, coloured by state
    states = {(t, c) for c, t in page.cells if t in ("alarm", "healthy")}
    assert states == {("alarm", "alarm txt"), ("healthy", "healthy txt")}
    assert "margin value/threshold [-]" in texts
    # kinematic tables with units: sun mesh 15.46 orders of the sun, sun fault order 2.441
    assert "mesh [Hz]" in texts and "speed [rpm]" in texts
    assert "15.46" in texts and "2.441" in texts
    # indicator table: the sun's FM4 value cell is highlighted, the ring's is not
    alarm_cells = [t for c, t in page.cells if "alarm" in c.split()]
    fm4 = verdict.components["planetary.sun"].indicators["FM4"]
    assert f"{fm4.value:.4g}" in alarm_cells
    assert "threshold [unit]" in texts and "unit" in texts
    text = path.read_text(encoding="utf-8")
    assert "alarms match the configured faults" in text
    assert re.search(r"tooth crack, 20% of the tooth thickness", text)


# ---------------------------------------------------------------- sensor band
def test_drawn_order_range_reaches_the_sensor_band() -> None:
    """Seed 004 ring accelerometer (examples/seed004_diagnose_sun_crack.toml): 5 kHz
    sampling, housing mode 1.2 kHz, sun (reference) at 32.4263 rpm = 0.540438 Hz. By hand:
    Nyquist order 2500/0.540438 = 4625.9, mode at order 1200/0.540438 = 2220.4; the
    features' spectrum reaches order 8192 (16384 samples/rev), so the drawn range is the
    Nyquist order — it used to stop at 3.3 × the sun mesh order 15.46 = 51."""
    f_ref = 32.4263 / 60.0
    band = sensor_band(8192.0, f_ref, 5000.0, [1200.0])
    assert band.nyquist_order == pytest.approx(4625.9, abs=0.1)
    assert band.order_max == band.nyquist_order
    assert band.modes_order == pytest.approx((2220.4,), abs=0.1)
    assert band.modes_order[0] < band.order_max and not band.truncated
    # an analysed spectrum stopping below the Nyquist order bounds the range (and says so)
    short = sensor_band(1024.0, f_ref, 5000.0, [0.0])
    assert short.order_max == 1024.0 and short.truncated and short.modes_hz == ()
    # no sample rate (angle-sampled channel): the whole analysed range
    assert sensor_band(512.0, f_ref).order_max == 512.0
    with pytest.raises(InputError, match="reference_hz"):
        sensor_band(512.0, 0.0, 5000.0)
    with pytest.raises(InputError, match="sample_rate_hz"):
        sensor_band(512.0, f_ref, float("nan"))


def test_sensor_band_figure_spans_the_band() -> None:
    """The drawn x range is [first positive order, order_max], log-log, units on both x axes
    (orders below, Hz on top) and on the amplitude axis."""
    spec = order_spectrum(np.random.default_rng(0).standard_normal(64 * 1024), 1024)
    spec.attrs["units"] = "m/s^2"
    band = sensor_band(512.0, 0.5, 300.0, [100.0])  # Nyquist order 150/0.5 = 300
    fig = sensor_band_figure(spec, None, band, None, "sun")
    ax = fig.axes[0]
    assert ax.get_xlim()[1] == pytest.approx(300.0)
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert ax.get_xlabel() == "order of sun [events/rev]"
    assert ax.get_ylabel() == "amplitude [m/s^2]"
    assert any("[Hz]" in a.get_xlabel() for a in fig.axes[0].child_axes)


def test_spectrogram_segment_resolves_the_lowest_mesh() -> None:
    """5 kHz, 50 s, lowest mesh 8.36 Hz → bins ≤ 4.18 Hz: 5000/4.18 = 1196 → 2048 samples
    (2.44 Hz); a short record keeps at least 4 segments (4000 samples: the largest power of
    two ≤ 4000/4 = 1000 is 512)."""
    assert spectrogram_segment(5000.0, 250_000, 4.18) == 2048
    assert spectrogram_segment(5000.0, 4000, 4.18) == 512
    assert spectrogram_segment(5000.0, 250_000, None) == 64


# ---------------------------------------------------------------- worst indicator
def _verdict_with_evidence():
    cfg = geardyn.load_config(EXAMPLES / "planetary_reclaimer.toml")
    freqs = characteristic_frequencies(geardyn.analyze_kinematics(cfg),
                                       dict(cfg.input_speeds_rpm))
    healthy = [synthetic_features(freqs, 0.0, s) for s in range(3)]
    faulty = synthetic_features(freqs, 1.0, 100)
    rule = ThresholdRule()
    verdict = judge(faulty.table, thresholds([h.table for h in healthy], rule), rule,
                    machine=cfg.name)
    # isolation evidence larger than every detection margin: never the "worst" indicator
    sun = verdict.components["planetary.sun"]
    fm4 = sun.indicators["FM4"]
    sun.indicators["SDR"] = replace(fm4, value=50.0, threshold=2.0, margin=25.0)
    return verdict, freqs, healthy, faulty


def test_chart_worst_is_the_table_worst() -> None:
    verdict, *_ = _verdict_with_evidence()
    table = verdict.table().set_index("component")
    rows = margin_rows(verdict)
    for r in rows:
        assert r.worst == table.loc[r.component, "worst_indicator"]
        assert r.worst_margin == table.loc[r.component, "margin"]
    sun = next(r for r in rows if r.component == "planetary.sun")
    assert sun.worst == "FM4" and sun.evidence == (25.0,)
    fig = margin_figure(verdict)
    ax = fig.axes[0]
    bars = [p.get_width() for p in ax.patches]
    assert bars == [float(table.loc[r.component, "margin"]) for r in rows]
    labels = [t.get_text().strip() for t in ax.texts]
    assert labels == [str(table.loc[r.component, "worst_indicator"]) for r in rows]


# ---------------------------------------------------------------- explanations, uncertain
def test_indicators_section_explains_every_indicator_shown(tmp_path: Path) -> None:
    verdict, freqs, healthy, faulty = _verdict_with_evidence()
    path = write_report(tmp_path, verdict, faulty, healthy=healthy[0], freqs=freqs)
    text = path.read_text(encoding="utf-8")
    assert "<h2>Indicators</h2>" in text
    page = PageChecker()
    page.feed(text)
    cells = [t for _, t in page.cells]
    for name in ("FM4", "skewness", "SDR"):
        ind = explain(name)
        assert ind.definition in cells and ind.reference in cells
    # skewness is judged on both sides; its unit and the indicator table's unit column
    assert "two-sided" in cells and "unit" in cells


def test_uncertain_state_detection_and_localisation_rendered(tmp_path: Path) -> None:
    verdict, freqs, healthy, faulty = _verdict_with_evidence()
    verdict.components["planetary.sun"].state = "uncertain"
    verdict.detection = {"detected": True, "false_alarm_probability": 0.01, "tests": 8,
                         "alpha_per_test": 0.00126,
                         "alarms": [{"component": "planetary.sun", "indicator": "FM4",
                                     "margin": 2.5}]}
    verdict.localisation = {"state": "uncertain", "components": [], "confidence": 0.55,
                            "candidates": [{"component": "planetary.sun", "posterior": 0.55,
                                            "evidence": "cSDR", "value": 1.8,
                                            "threshold": 2.4},
                                           {"component": "planetary.ring", "posterior": 0.45,
                                            "evidence": "cSDR", "value": 1.5,
                                            "threshold": 2.4}],
                            "score": "posterior of each location hypothesis"}
    path = write_report(tmp_path, verdict, faulty, healthy=healthy[0], freqs=freqs)
    text = path.read_text(encoding="utf-8")
    page = PageChecker()
    page.feed(text)
    page.close()
    assert page.errors == [] and page.stack == []
    assert ("uncertain txt", "uncertain") in page.cells  # state cell coloured
    assert "td.uncertain{" in text
    assert text.index("Detection and localisation") < text.index("<h2>Verdict</h2>")
    assert "Detection: Fault detected." in text
    assert "false-alarm probability 0.01 over 8 tests" in text
    assert ("Localisation: Location uncertain; candidates planetary.sun, planetary.ring "
            "(confidence 0.55).") in text
    assert "Uncertain (detected, not localised): planetary.sun." in text
    # margin chart: the uncertain component's bar is amber
    from matplotlib.colors import to_rgba

    fig = margin_figure(verdict)
    i = [r.component for r in margin_rows(verdict)].index("planetary.sun")
    assert fig.axes[0].patches[i].get_facecolor() == pytest.approx(to_rgba("tab:orange", 0.6))


def test_report_without_detection_attributes(tmp_path: Path) -> None:
    """Today's verdict (no detection/localisation) renders without that section."""
    verdict, freqs, healthy, faulty = _verdict_with_evidence()
    for attr in ("detection", "localisation"):
        if hasattr(verdict, attr):
            setattr(verdict, attr, None)
    text = write_report(tmp_path, verdict, faulty, freqs=freqs).read_text(encoding="utf-8")
    assert "Detection and localisation" not in text and "<h2>Verdict</h2>" in text
