"""Seed 003 Table 3.2 / Table 3.6 (36-DOF Model A, low band): not reproducible from the
printed Table 3.1 — proved from the thesis's own numbers in test_table_3_2_consistency.py (a
translational mode ≤ 140 Hz and a rotational one ≤ 40 Hz must exist; Table 3.2 has none below
193 and 118 Hz). Our own values are pinned as regression guards."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.config.loader import load_config
from geardyn.models.planetary.build import model_from_config
from geardyn.models.planetary.modal import modes

from ._bench import EX


@pytest.fixture(scope="module")
def low_band():
    r = modes(model_from_config(load_config(EX / "planetary_bench_36dof.toml")))
    rows = r.table()
    return [row for row in rows if 0.5 < row["freq_hz"] < 1000.0]


def test_test_ring_rotation_mode_pinned(low_band):
    # regression guard (no source value): the rotational mode dominated by test.ring.u, 527.5 Hz
    # (7.9e6 read as N·m/rad). Table 3.6's 550 Hz is no reference: Tables 3.2/3.6 contradict
    # Table 3.1 (test_table_3_2_consistency.py), and their 547/550 Hz pair for the free and the
    # held ring needs a support much softer than the ring meshes — the printed N/m unit, with
    # which this mode is at 71.6 Hz (docs/validation.md, Hammami 2015 section).
    hit = [r for r in low_band if r["dominant_motion"] == "test.ring.u"]
    assert len(hit) == 1 and hit[0]["type"] == "rotational"
    assert hit[0]["freq_hz"] == pytest.approx(527.5358, rel=1e-4)


def test_low_band_pinned(low_band):
    # regression guard (no source value): Table 3.2 (118, 136, 193, 244, 247, 288, 344, 376,
    # 387, 536, 547, 550 Hz) is not reproduced by the Table 3.1 parameters (notes §4.2: no
    # choice of α, r_c, stiffness swap or unit reading does); these are our model's values
    # (examples/planetary_bench_36dof.toml), kept to 1e-4.
    f = np.array([r["freq_hz"] for r in low_band])
    expected = [26.8715, 139.9552, 139.9552, 139.9580, 139.9580, 258.2606, 258.2606, 258.3239,
                258.3239, 259.4238, 262.3094, 343.8931, 527.5358, 984.6690]
    np.testing.assert_allclose(f, expected, rtol=1e-4)


def test_low_band_types_and_dominant_motion_pinned(low_band):
    # regression guard (no source value): Table 3.6 lists 8 rotational + 4 translational low
    # modes with carrier/planet/ring motions that our parameters do not give; pinned: type and
    # dominant motion per distinct frequency (first of each degenerate group).
    seen: dict[float, tuple[str, str]] = {}
    for r in low_band:
        seen.setdefault(round(r["freq_hz"], 1), (r["type"], r["dominant_motion"].split(".")[-1]))
    assert seen == {
        26.9: ("rotational", "u"),  # reaction ring winding the loop through the planet bearings
        140.0: ("translational", "y"),  # ring translation on 2.1e7 N/m (no carrier rotation)
        258.3: ("translational", "zeta"),  # planets on 3.5e6 N/m bearings
        259.4: ("rotational", "zeta"),
        262.3: ("rotational", "zeta"),
        343.9: ("rotational", "u"),  # test carrier rotation
        527.5: ("rotational", "u"),  # test ring rotation
        984.7: ("rotational", "u"),  # test sun rotation on the sun shaft
    }
