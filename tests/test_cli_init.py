"""``geardyn init``, ``geardyn schema``, the config reference, help texts, JSON numbers, table
widths and lazy imports (issue 13 item 5)."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest
from typer.testing import CliRunner

from geardyn.cli import COMMANDS, app
from geardyn.config import load_config

runner = CliRunner()


@pytest.mark.parametrize(
    ("template", "command"),
    [
        ("parallel", ["kinematics"]),
        ("parallel", ["stiffness", "--samples", "16"]),
        ("planetary", ["modes"]),
        ("transmission", ["transmission", "--revolutions", "0.05"]),
        ("differential", ["kinematics"]),
    ],
)
def test_init_templates_load_and_run(tmp_path, template, command):
    path = tmp_path / f"{template}.toml"
    r = runner.invoke(app, ["init", template, str(path)])
    assert r.exit_code == 0, r.output
    text = path.read_text()
    assert text.count("\n#") >= 5  # commented
    load_config(path)
    r = runner.invoke(app, [command[0], str(path), *command[1:]])
    assert r.exit_code == 0, r.output


@pytest.mark.slow
@pytest.mark.parametrize("template", ["parallel", "planetary", "transmission", "differential"])
def test_init_simulate_diagnose_reaches_a_verdict(tmp_path, monkeypatch, template):
    """Issue 21: each template, as written, simulates and diagnoses (≈ 3 s + 10 s each on one
    core; the simulated durations are kept short in the templates)."""
    monkeypatch.chdir(tmp_path)
    assert runner.invoke(app, ["init", template]).exit_code == 0
    r = runner.invoke(app, ["simulate", f"{template}.toml", "--out", "run.nc"])
    assert r.exit_code == 0, r.output
    assert "sensor channel(s)" in r.output
    r = runner.invoke(app, ["diagnose", f"{template}.toml", "--out", "diagnosis"])
    assert r.exit_code == 0, r.output
    assert "detection" in r.output and "isolation" in r.output  # the two margins, named
    assert "None" not in r.output
    verdict = json.loads((tmp_path / "diagnosis" / "verdict.json").read_text())
    assert verdict["summary"]["verdict"] in {"alarm", "healthy", "uncertain"}
    assert verdict["components"]  # every component judged
    # provenance (issue 21): version, UTC time, the config's bytes, operating point, units
    import datetime
    import hashlib

    import geardyn

    assert verdict["geardyn_version"] == geardyn.__version__
    created = datetime.datetime.fromisoformat(verdict["created_utc"])
    assert created.utcoffset() == datetime.timedelta(0)
    assert abs((datetime.datetime.now(datetime.UTC) - created).total_seconds()) < 600
    cfg_bytes = (tmp_path / f"{template}.toml").read_bytes()
    assert verdict["config"]["sha256"] == hashlib.sha256(cfg_bytes).hexdigest()
    speeds = verdict["operating_point"]["input_speeds"]
    assert speeds and all(v["unit"] == "rpm" and v["value"] > 0 for v in speeds.values())
    assert verdict["units"]["margin"].startswith("1")
    assert verdict["units"]["t_end_s, skip_s"] == "s"
    import html
    import re

    report = (tmp_path / "diagnosis" / "report.html").read_text()
    text = html.unescape(re.sub(r"<[^>]+>", " ", re.sub(
        r"<(style|script)\b.*?</\1>", "", re.sub(r"<img[^>]*>", "", report), flags=re.S)))
    assert "None" not in text  # a missing value prints "–"
    assert "Input speeds: " in text and " rpm" in text and "{" not in text.split(
        "Input speeds: ")[1][:80]


@pytest.mark.parametrize(("cut", "message"), [
    ("[[sensors]]", "sensors: diagnose needs at least one signal sensor"),
    ("[dynamics]", "nothing to simulate"),
])
def test_diagnose_checks_model_and_sensors_before_any_run(tmp_path, monkeypatch, cut, message):
    """A config without sensors (or without a dynamic model) is refused before anything is
    simulated and before the output folder is created."""
    import geardyn.run

    def no_run(*a, **k):  # noqa: ANN002, ANN003, ANN202
        raise AssertionError("simulated before checking the config")

    monkeypatch.setattr(geardyn.run, "run_simulation", no_run)
    from geardyn.templates import render

    text = render("parallel", "p.toml")
    path = tmp_path / "p.toml"
    path.write_text(text[:text.index(cut)])
    r = runner.invoke(app, ["diagnose", str(path), "--out", str(tmp_path / "d")])
    assert r.exit_code == 2 and message in r.output, r.output
    assert not (tmp_path / "d").exists()
    path.write_text(text)
    r = runner.invoke(app, ["diagnose", str(path), "--out", str(tmp_path / "d"),
                            "--channel", "tacho_input"])
    assert r.exit_code == 2 and "is not a signal sensor" in r.output, r.output
    r = runner.invoke(app, ["diagnose", str(path), "--out", str(tmp_path / "d"),
                            "--reference", "nope"])
    assert r.exit_code == 2 and "--reference" in r.output and "nope" in r.output, r.output
    r = runner.invoke(app, ["diagnose", str(path), "--out", str(tmp_path / "d"),
                            "--reference", "housing"])  # the frame does not turn
    assert r.exit_code == 2 and "--reference" in r.output, r.output
    assert not (tmp_path / "d").exists()


def test_init_refuses_unknown_template_and_overwrite(tmp_path):
    r = runner.invoke(app, ["init", "helical", str(tmp_path / "x.toml")])
    assert r.exit_code == 2 and "TEMPLATE: unknown template 'helical'" in r.output
    path = tmp_path / "p.toml"
    assert runner.invoke(app, ["init", "parallel", str(path)]).exit_code == 0
    r = runner.invoke(app, ["init", "parallel", str(path)])
    assert r.exit_code == 2 and "exists" in r.output
    assert runner.invoke(app, ["init", "parallel", str(path), "--force"]).exit_code == 0


def test_config_reference_is_up_to_date():
    from geardyn.config.reference import default_path, reference_markdown

    assert default_path().read_text() == reference_markdown(), (
        "docs/config.md is out of date: run python -m geardyn.config.reference")


def test_schema_lists_sections_and_accepts_units(tmp_path):
    out = tmp_path / "s.json"
    r = runner.invoke(app, ["schema", "--out", str(out)])
    assert r.exit_code == 0, r.output
    schema = json.loads(out.read_text())
    assert {"planetary_dynamics", "transmission", "sensors", "gear_geometry"} <= set(
        schema["properties"])
    module = schema["$defs"]["GearGeometryConfig"]["properties"]["normal_module_m"]
    kinds = [o.get("type") for o in module["anyOf"]]
    assert "number" in kinds and "string" in kinds  # "3 mm" allowed


def test_help_texts_keep_brackets():
    r = runner.invoke(app, ["stiffness", "--help"], terminal_width=100)
    assert "[[gear_geometry]]" in r.output
    r = runner.invoke(app, ["analyze", "--help"], terminal_width=100)
    assert "[s]" in r.output and "[Hz]" in r.output


def test_top_help_lists_every_command():
    r = runner.invoke(app, ["--help"], terminal_width=100)
    assert r.exit_code == 0
    for name in COMMANDS:
        assert name in r.output


def test_kinematics_json_has_numeric_ratios(examples_dir):
    r = runner.invoke(app, ["kinematics", str(examples_dir / "car_differential.toml"), "--json"])
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    pinion = next(row for row in data["links"] if row["link"] == "drive_pinion")
    # seed 000 Table 1: the drive pinion turns at -2.5 × each wheel speed (both inputs)
    for ratio in pinion["ratio"].values():
        assert ratio["real"] == pytest.approx(-2.5, rel=1e-9)
        assert ratio["magnitude"] == pytest.approx(2.5, rel=1e-9)
        assert abs(ratio["angle_deg"]) == pytest.approx(180.0)


def _table_width(text: str) -> int:
    return max((len(line) for line in text.splitlines() if line[:1] in "┏┃│└┡"), default=0)


@pytest.mark.parametrize(("example", "last_column"), [("car_differential.toml", "ratio"),
                                                      ("seed002_transmission.toml", "bsf_order")])
def test_kinematics_tables_fit_100_columns(examples_dir, example, last_column):
    r = runner.invoke(app, ["kinematics", str(examples_dir / example)])
    assert r.exit_code == 0, r.output
    assert 0 < _table_width(r.output) <= 100
    assert last_column in r.output  # wide tables split into parts, not cut


def test_stiffness_rows_carry_their_unit(examples_dir):
    from geardyn.cli.stiffness import summary_row

    assert summary_row("centre_distance_m", 0.1455) == ("centre_distance (mm)", "145.5000")
    assert summary_row("working_pressure_angle_deg", 20.0)[0] == "working_pressure_angle (deg)"
    r = runner.invoke(app, ["stiffness", str(examples_dir / "seed002_two_stage.toml"),
                            "--pair", "low", "--samples", "16"])
    assert r.exit_code == 0, r.output
    assert "centre_distance (mm)" in r.output and "_m " not in r.output
    # 145.5 mm = m_n (z1 + z2) / 2 = 3 mm × 97 / 2 (spur low stage of seed 002 Table 2)
    assert "145.5000" in r.output


def test_import_geardyn_is_light():
    code = ("import sys, geardyn; heavy = [m for m in ('pandas', 'xarray', 'matplotlib', "
            "'scipy', 'pint') if m in sys.modules]; print(','.join(heavy))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == ""


def test_accessor_registered_when_xarray_is_imported():
    code = ("import geardyn, xarray as xr; print(hasattr(xr.Dataset(), 'geardyn'))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "True"


def test_units_in_config_strings(tmp_path):
    from geardyn.config.units import to_unit

    assert to_unit("3 mm", "m", "a length") == pytest.approx(0.003)
    assert to_unit("25 Hz", "rpm", "a rotational speed") == pytest.approx(1500.0)
    assert to_unit("157.0796327 rad/s", "rpm", "a rotational speed") == pytest.approx(1500.0)
    assert to_unit("1500 rpm", "Hz", "a frequency") == pytest.approx(25.0)
    assert to_unit("0.5", "deg", "an angle") == 0.5  # no unit: the field's unit
    assert to_unit("1 rad", "deg", "an angle") == pytest.approx(math.degrees(1.0))
    with pytest.raises(ValueError, match="'3 rpm' is not a length"):
        to_unit("3 rpm", "m", "a length")
    cfg = tmp_path / "u.toml"
    from geardyn.templates import render

    text = render("parallel", "u.toml").replace("normal_module_m = 0.003",
                                                 'normal_module_m = "3 mm"')
    assert "input = 1470.0" in text
    text = text.replace("input = 1470.0", 'input = "24.5 Hz"')
    cfg.write_text(text)
    c = load_config(cfg)
    assert c.gear_geometry[0].normal_module_m == pytest.approx(0.003)
    assert c.input_speeds_rpm["input"] == pytest.approx(1470.0)  # 24.5 Hz × 60 s/min


def _numeric_fields():
    import typing

    from pydantic import BaseModel

    from geardyn.config import GeardynConfig

    seen, out = set(), []

    def walk(model):
        if model in seen:
            return
        seen.add(model)
        for name, field in model.model_fields.items():
            def sub(t):
                if isinstance(t, type) and issubclass(t, BaseModel):
                    walk(t)
                for a in typing.get_args(t):
                    sub(a)
            sub(field.annotation)
            text = str(field.annotation)
            if ("float" in text or "int" in text) and "BaseModel" not in text:
                out.append((model.__name__, name))

    walk(GeardynConfig)
    return out


def test_every_unit_suffix_of_the_models_is_known():
    """Every numeric field whose name ends in a unit-like token carries a suffix of
    config.units.SUFFIXES (so "3 mm" strings convert and magnitudes are checked)."""
    from geardyn.config.units import SUFFIXES, field_suffix

    unit_like = {"mm", "cm", "um", "km", "g", "mpa", "gpa", "kpa", "kn", "knm", "khz", "ms",
                 "min", "h", "rads", "degs", "mm2", "nmm", "kw", "bar", "mps"}
    fields = _numeric_fields()
    assert len(fields) > 100
    unknown = [f"{m}.{n}" for m, n in fields if n.rsplit("_", 1)[-1] in unit_like]
    assert not unknown, f"add these unit suffixes to config.units.SUFFIXES: {unknown}"
    used = {field_suffix(n)[0] for _, n in fields if field_suffix(n)}
    assert {"_m", "_deg", "_rpm", "_s", "_hz", "_kg", "_kgm2", "_n_per_m", "_nm",
            "_pa"} <= used
    for suffix, info in SUFFIXES.items():  # each unit parses and has the stated dimension
        from geardyn.config.units import to_unit

        assert to_unit(f"2 {info.unit}", info.unit, info.what) == pytest.approx(2.0), suffix


def test_top_help_imports_no_command_module():
    """``geardyn --help`` lists the commands from cli.COMMANDS without importing them (nor
    pandas, xarray, matplotlib): start-up stays well under a second (benchmarks/bench_startup)."""
    code = ("import sys\nfrom geardyn.cli import app\ntry:\n    app(['--help'])\n"
            "except SystemExit:\n    pass\n"
            "mods = [m for m in sys.modules if m.startswith('geardyn.cli.') and "
            "m.rsplit('.', 1)[1] in __import__('geardyn.cli').cli.COMMANDS]\n"
            "heavy = [m for m in ('pandas', 'xarray', 'matplotlib', 'scipy') if m in sys.modules]\n"
            "print('MODS', mods, heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert "MODS [] []" in out
