"""Wang 2010 (seed 004) §8.3, Fig 8-28: an output of the combined transmission error. "When the
combined gear error has been introduced into the simulation (case-3), … the signal
irregularity is increased and enhanced in the vibration signal as compared to that of case-2"
(carrier arm torsional speed, averaged signal). Case 2: carrier arm + bucket wheel + buckets
(Table 6-4, before loading) under the rated load that Fig 8-8 implies (test_startup.py), started
at the steady speed; case 3: the same with the combined error of §4.3. The averaged signal is the
synchronous average over z_s = 19 mesh cycles (a sun revolution relative to the carrier, §8.2),
three of them from 1 s on."""

from __future__ import annotations

import numpy as np
import pytest

from ._reclaimer import R_C, ZR, ZS, run

pytestmark = pytest.mark.slow  # two 8 s runs (≈ 1 s)


def _case(d: dict) -> None:
    sim = d["planetary_dynamics"]["simulation"]
    st = d["planetary_dynamics"]["stages"][0]
    sim["initial_speed_rpm"] = {"motor": 952.5, "sun": 5.8885 * 5.3684}  # steady, rated load
    sim["wheel_load"]["control_ratio"] = 1.0
    st["carrier"]["mass_kg"], st["carrier"]["inertia_kgm2"] = 26431.0, 92926.0


def _averaged(ds, dof: str, spc: int = 64, t0: float = 1.0) -> np.ndarray:
    t = ds.time.values
    x = ZR * ds.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
    s = t > t0
    x0 = np.ceil(x[s][0])
    n_rev = int((x[s][-1] - x0) // ZS)
    g = x0 + np.arange(n_rev * ZS * spc) / spc
    y = np.interp(g, x[s], ds.v.sel(dof=dof).values[s])
    return y.reshape(n_rev, -1).mean(0)


def _mesh_share(avg: np.ndarray) -> float:
    """Share of the averaged signal's variance at integer mesh orders."""
    p = np.abs(np.fft.rfft(avg - avg.mean())) ** 2
    return float(p[ZS::ZS].sum() / p.sum())


def test_fig_8_28_error_makes_the_carrier_signal_irregular():
    """The thesis states the direction only (no number): with the error the carrier's averaged
    torsional speed is less regular — a smaller share of its variance at the mesh orders
    (measured 1.00 → 0.68) and a larger peak to peak (× 1.76). Not reproduced, and not tested:
    the same statements for the sun (Fig 8-27; our sun share stays 0.59) and the "slightly
    increased" speeds (ours equal to 1e-5); with the Table 7-1 planet-bearing damper the
    error's effect drowns in the stiffness-step ripple (share 0.999 both)."""
    out = {}
    for te in (False, True):
        _, ds = run([], 8.0, te=te, edit=_case)
        avg = _averaged(ds, "carrier.u")
        out[te] = (_mesh_share(avg), float(np.ptp(avg)))
    assert out[True][0] < out[False][0]
    assert out[True][1] > out[False][1]
