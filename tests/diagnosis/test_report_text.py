"""Report text without Python reprs (issue 21): no "None", no dict braces, units on settings."""

from __future__ import annotations

from geardyn.diagnosis.report import _fmt, _setting


def test_values_print_without_python_reprs():
    assert _fmt(None) == "–"
    assert _fmt(float("nan")) == "–"
    assert _fmt({"sun": 34.01818361952387}) == "sun 34.02"
    assert _fmt([0, 1, 2]) == "0, 1, 2"
    assert _fmt(True) == "yes"


def test_settings_carry_units_and_skip_unset_values():
    assert _setting("baseline", "t_end_s", None) is None  # the config's own value: not "None"
    assert _setting("baseline", "skip_s", 0.5) == ("baseline skip [s]", "0.5")
    assert _setting("record", "seed", 100) == ("record seed", "100")
    label, text = _setting("baseline", "members", [{}, {}, {}])
    assert label == "baseline ensemble members" and text.startswith("3 ")
