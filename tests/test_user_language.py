"""The user's language (issue 21): user-facing text cites the literature by author, year and
equation ("Wang 2010, eq 6.6"), never the project's internal document numbers ("seed 004 eq
2"); "seed" then means only the random seed. Checked on every command's help, the JSON schema,
the kinematic output of every example, a diagnosis (terminal, verdict.json, report.html), the
README and the docs. Code comments and tests may keep the internal numbers."""

from __future__ import annotations

import json
import re
from pathlib import Path

import click
import pytest
from typer.main import get_command
from typer.testing import CliRunner

from geardyn.cli import app

ROOT = Path(__file__).resolve().parents[1]
#: An internal document number: "seed 004", "Seed 002", "seeds 003".
INTERNAL = re.compile(r"\bseeds? 0\d\d\b", re.IGNORECASE)
#: docs pages kept by other work in progress (issue 21 brief): checked when they are rewritten.
DOCS_ELSEWHERE = {"detectability.md", "validation.md"}

runner = CliRunner()


def _internal(text: str) -> list[str]:
    return sorted({text[max(0, m.start() - 30):m.end() + 10].replace("\n", " ")
                   for m in INTERNAL.finditer(text)})


def test_pattern_finds_internal_numbers():
    assert _internal("cf. seed 002 Fig 9") and _internal("(Seed 004)")
    assert not _internal("Thibault et al. 2024, Fig 9; record seed 100; seed004_planetary.toml")


def test_every_help_text_cites_authors():
    group = get_command(app)
    ctx = click.Context(group)
    texts = {"geardyn": runner.invoke(app, ["--help"], terminal_width=200).output}
    for name in group.list_commands(ctx):
        texts[name] = runner.invoke(app, [name, "--help"], terminal_width=200).output
    found = {name: _internal(t) for name, t in texts.items() if _internal(t)}
    assert not found, found


def test_schema_descriptions_cite_authors(tmp_path):
    out = tmp_path / "schema.json"
    assert runner.invoke(app, ["schema", "--out", str(out)]).exit_code == 0
    assert not _internal(out.read_text())


@pytest.mark.parametrize("example", sorted(p.name for p in (ROOT / "examples").glob("*.toml")))
def test_example_names_cite_authors(example):
    """A config's ``name`` heads every table and verdict printed for it."""
    import tomllib

    data = tomllib.loads((ROOT / "examples" / example).read_text())
    assert not _internal(str(data.get("name", ""))), data.get("name")


def test_kinematics_output_cites_authors():
    for name in ("car_differential.toml", "alouette3_mgb.toml", "hammami_back_to_back.toml",
                 "reclaimer_drive.toml"):
        r = runner.invoke(app, ["kinematics", str(ROOT / "examples" / name)],
                          terminal_width=200)
        assert r.exit_code == 0, r.output
        assert not _internal(r.output), (name, _internal(r.output))


def test_readme_and_docs_cite_authors():
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    found = {p.name: _internal(p.read_text()) for p in pages
             if p.name not in DOCS_ELSEWHERE and _internal(p.read_text())}
    assert not found, found
    assert "../shared" not in (ROOT / "README.md").read_text()  # stands alone in a clone


def verdict_problems(verdict: dict) -> list[str]:
    """What a verdict.json breaks of issue 21: a count ``n: 0`` beside a number for its mean
    or standard deviation (a statistic of nothing), the text "None" anywhere, and localisation
    candidates whose value/threshold differ from the same component's indicator entry (one
    source of truth for the report's notes and table)."""
    out = []

    def walk(o: object, path: str) -> None:
        if isinstance(o, dict):
            if o.get("n") == 0 and any(isinstance(o.get(k), float | int) for k in
                                       ("mean", "std", "sigma")):
                out.append(f"{path}: n = 0 beside a mean/std {o}")
            for k, v in o.items():
                walk(v, f"{path}/{k}")
        elif isinstance(o, list):
            for i, v in enumerate(o):
                walk(v, f"{path}[{i}]")
        elif isinstance(o, str) and "None" in o:
            out.append(f"{path}: {o!r}")

    walk(verdict, "")
    for cand in (verdict.get("localisation") or {}).get("candidates", []):
        ind = verdict["components"][cand["component"]]["indicators"].get(cand["evidence"])
        if ind is None:
            out.append(f"localisation candidate {cand} has no indicator entry")
        elif (ind["value"], ind["threshold"]) != (cand["value"], cand["threshold"]):
            out.append(f"localisation {cand} disagrees with the table {ind}")
    return out


def test_verdict_problems_are_found():
    bad = {"a": {"n": 0, "mean": 1.0, "std": 0.1}, "notes": ["speed None rpm"],
           "components": {"x": {"indicators": {"cSDR": {"value": 0.467, "threshold": 1.0}}}},
           "localisation": {"candidates": [{"component": "x", "evidence": "cSDR",
                                            "value": 0.234, "threshold": 1.0}]}}
    assert len(verdict_problems(bad)) == 3


@pytest.mark.slow
def test_diagnosis_outputs_cite_authors(tmp_path, monkeypatch):
    """Terminal output, verdict.json and report.html of a diagnosis (the planetary template,
    about 10 s)."""
    monkeypatch.chdir(tmp_path)
    assert runner.invoke(app, ["init", "planetary"]).exit_code == 0
    r = runner.invoke(app, ["diagnose", "planetary.toml", "--out", "d"], terminal_width=200)
    assert r.exit_code == 0, r.output
    assert not _internal(r.output)
    verdict = (tmp_path / "d" / "verdict.json").read_text()
    assert not verdict_problems(json.loads(verdict))
    assert not _internal(verdict), _internal(verdict)
    report = (tmp_path / "d" / "report.html").read_text()
    report = re.sub(r'src="data:[^"]*"', "", report)  # embedded figures: base64, not text
    assert not _internal(report), _internal(report)
    # levels in the analysed channel's unit show that unit, not "channel units"
    table = report.split("Indicators and thresholds", 1)[1].split("<h2", 1)[0]
    assert "channel units" not in table and "m/s" in table
