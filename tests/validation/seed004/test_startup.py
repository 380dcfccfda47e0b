"""Seed 004 §8.2 case 1 start-up and the case 1 / case 2 speed fluctuation (Figs 8-1, 8-13 to
8-16, 8-28): "steady state ... achieved within 0.3 s"; the averaged carrier torsional speed of
case 1 "varies in a large range from approximately 5 to 6 rpm"; with the bucket wheel (case 2)
"the signal fluctuation range is reduced by a factor of 10 times".

Case 1: no bucket wheel, no load, no transmission error (the example without ``wheel_load``);
case 2: bucket-wheel load schedule and inertia schedule on. Start from rest (the thesis's
initial conditions are not given, notes §6 item 10)."""

from __future__ import annotations

import numpy as np
import pytest

from ._reclaimer import R_C, run

RPM = 60 / (2 * np.pi)


def _edit(case: int, from_rest: bool):
    def edit(d: dict) -> None:
        sim = d["planetary_dynamics"]["simulation"]
        if from_rest:
            sim["initial_speed_rpm"] = {}
        if case == 1:
            del sim["wheel_load"]
        else:
            sim["wheel_load"]["schedule"] = True
            sim["wheel_load"]["inertia_schedule"] = True
    return edit


def _carrier_rpm(ds) -> tuple[np.ndarray, np.ndarray]:
    return ds.time.values, ds.v.sel(dof="carrier.u").values / R_C * RPM


@pytest.fixture(scope="module")
def case1():
    return run([], 2.0, edit=_edit(1, True))[1]


def test_case1_startup_within_0_3_s(case1):
    """From rest, the carrier speed stays within 5 % of its final value (mean over 1.5-2 s)
    from t < 0.3 s on (seed 004 Fig 8-13: steady state within 0.3 s). The final speed is the
    no-load motor speed (1000 rpm synchronous) through 29.2971 × 5.3684: 6.36 rpm (1 %)."""
    t, rpm = _carrier_rpm(case1)
    final = rpm[t > 1.5].mean()
    assert final == pytest.approx(1000 / (29.2971 * 5.3684), rel=0.01)
    outside = np.flatnonzero(np.abs(rpm - final) > 0.05 * final)
    assert t[outside[-1] + 1] < 0.3


def test_case1_fluctuation_pinned(case1):
    # regression guard (no source value): the thesis's case 1 carrier speed spans ≈ 5-6 rpm
    # (≈ 1 rpm peak to peak, Fig 8-28, averaged signal of a MATLAB ode15s run whose tolerances
    # are not given); ours settles to a fluctuation of 0.16 rpm peak to peak at 1-2 s. Pinned
    # to 20 %.
    t, rpm = _carrier_rpm(case1)
    assert np.ptp(rpm[t > 1.0]) == pytest.approx(0.163, rel=0.2)


@pytest.mark.slow
def test_case2_fluctuation_smaller_than_case1():
    """Case 2 (bucket wheel) fluctuates less than case 1 at steady state (both from the nominal
    speed, 2-3 s). The thesis's factor 10 is not reproduced; regression guard (no source
    value): our ratio 3.6 (to 25 %)."""
    p2p = []
    for case in (1, 2):
        _, ds = run([], 3.0, edit=_edit(case, False))
        t, rpm = _carrier_rpm(ds)
        p2p.append(np.ptp(rpm[t > 2.0]))
    assert p2p[1] < p2p[0]
    assert p2p[0] / p2p[1] == pytest.approx(3.6, rel=0.25)
