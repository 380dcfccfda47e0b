"""report.html from synthetic features: one self-contained page that parses (balanced tags,
every image a PNG data URI) and holds the verdict, kinematic and indicator tables."""

from __future__ import annotations

import base64
import re
from html.parser import HTMLParser
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import xarray as xr

import geardyn
from geardyn.diagnosis.baseline import ThresholdRule, thresholds
from geardyn.diagnosis.faults import fault_list
from geardyn.diagnosis.report import write_report
from geardyn.diagnosis.verdict import judge
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
    assert "threshold [-]" in texts
    text = path.read_text(encoding="utf-8")
    assert "alarms match the configured faults" in text
    assert re.search(r"tooth crack, 20% of the tooth thickness", text)
