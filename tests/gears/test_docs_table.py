"""The PE vs ISO 6336 table in docs/stiffness.md matches what the code computes."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from geardyn.config import load_config
from geardyn.config.gears import pair_model
from geardyn.gears.pe_stiffness import mesh_stiffness
from geardyn.gears.simple import iso_mesh_stiffness, iso_single_pair_stiffness

ROOT = Path(__file__).resolve().parents[2]
ROWS = {
    "seed 002 low": ("seed002_two_stage.toml", "low"),
    "seed 002 high": ("seed002_two_stage.toml", "high"),
    "seed 004 sun–planet": ("seed004_planetary.toml", "plan.sun-planet1"),
    "seed 004 ring–planet": ("seed004_planetary.toml", "plan.ring-planet1"),
}


def _doc_rows() -> dict[str, list[str]]:
    text = (ROOT / "docs" / "stiffness.md").read_text()
    out = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells and cells[0] in ROWS:
            out[cells[0]] = cells
    return out


@pytest.mark.parametrize("label", list(ROWS))
def test_docs_iso_table_row(label):
    cells = _doc_rows()[label]
    path, name = ROWS[label]
    g = pair_model(load_config(ROOT / "examples" / path), name).geometry
    t = mesh_stiffness(g, n_per_cycle=512, n_slices=None if g.helix_angle == 0 else 48)
    kpe = t.total.mean() / g.face_width / 1e9
    c = iso_single_pair_stiffness(
        g.a.teeth,
        g.b.teeth,
        g.a.profile_shift,
        g.b.profile_shift,
        g.helix_angle,
        g.normal_pressure_angle,
        1.25,
        g.internal,
        e_ratio=g.a.material.youngs_modulus / 206e9,
    )
    cga = iso_mesh_stiffness(c, g.contact_ratio) / 1e9
    assert float(cells[3]) == pytest.approx(g.contact_ratio, abs=1e-4)
    assert float(cells[4]) == pytest.approx(kpe, abs=0.006)
    assert float(cells[5]) == pytest.approx(cga, abs=0.006)
    pct = float(re.sub(r"[^\d.+-]", "", cells[6].replace("−", "-")))
    assert pct == pytest.approx(round((kpe - cga) / cga * 100), abs=0.5)
    assert float(cells[8]) == pytest.approx(c / 1e9, abs=0.006)
