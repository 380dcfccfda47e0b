"""Every config under examples/ loads; those with input speeds run the kinematics."""

from __future__ import annotations

from pathlib import Path

import pytest

from geardyn import analyze_kinematics, load_config
from geardyn.kinematics import characteristic_frequencies

EXAMPLES = sorted((Path(__file__).resolve().parents[1] / "examples").glob("*.toml"))


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_loads_and_runs_kinematics(path):
    cfg = load_config(path)
    if not cfg.gear_pairs and not cfg.planetary and not cfg.parallel and not cfg.bevel:
        pytest.skip("no mechanism gears in this example")
    kin = analyze_kinematics(cfg)
    assert kin.dof >= 1
    if cfg.input_speeds_rpm:
        f = characteristic_frequencies(kin, dict(cfg.input_speeds_rpm))
        assert (f.meshes["mesh_hz"] > 0).any()
