"""Seed 002 §3.4-3.5 results on the low-speed shaft IAS, [360 – 430 rpm / 20 rev]: Fig 14
(bearing spall), Fig 17 (crack 15 % vs 25 %), Fig 18 (crack vs spall), Fig 19 (cepstrum),
Fig 20 (double impulse), and the resonance band of Fig 10. Five FE runs (≈ 5 s each)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.ndimage import median_filter

from geardyn.config import load_config
from geardyn.config.gears import pair_model
from geardyn.config.loader import parse_config
from geardyn.gears.faults import Crack
from geardyn.gears.pe_stiffness import mesh_stiffness
from geardyn.models.transmission.assembly import build_model
from geardyn.models.transmission.simulate import prepare
from geardyn.signal.cepstrum import real_cepstrum

from ._runs import BPFO, EXAMPLE, HIGH_MESH, PPR, ROOT_CHORD, detrended, mean_difference, spectrum

pytestmark = pytest.mark.slow


def _amp(case: str, order: float) -> float:
    o, a = spectrum(case)
    i = int(np.argmin(np.abs(o - order)))
    return float(a[i - 1 : i + 2].max())


def _gains(case: str, ref: str, orders) -> np.ndarray:  # noqa: ANN001
    return np.array([_amp(case, k) / _amp(ref, k) for k in orders])


def test_fig14_bearing_spall_harmonics_rise_sidebands_coincide() -> None:
    """Fig 14: BPFO harmonics rise with the outer-race spall (reproduced: harmonics 1-7 × > 5).
    The seed's decrease of the sidebands 69.40 ± k·BPFO around the high-stage mesh order is not
    observable separately: at the seed's parameters 15·BPFO = 69.40 (Table 3 bearing, Table 2
    teeth), so those sidebands fall on BPFO harmonics 14, 16, 13, 17 within 0.002 order (the
    resolution is 1/18 order), and the harmonics dominate."""
    assert _gains("bearing_spall", "healthy", [k * BPFO for k in range(1, 8)]).min() > 5.0
    assert abs(HIGH_MESH - 15 * BPFO) < 0.002
    # regression guard (no source value): our sidebands at 69.40 ± k·BPFO rise (× 6-55)
    side = [HIGH_MESH + s * k * BPFO for k in (1, 2) for s in (-1, 1)]
    assert _gains("bearing_spall", "healthy", side).min() > 3.0


def test_fig17_deeper_crack_raises_integer_orders_as_the_stiffness_loss() -> None:
    """Fig 17: integer orders grow with crack depth (15 % → 25 % of the tooth thickness). The
    growth matches an independent quasi-static estimate — the IAS perturbation of a linear
    system scales with the mesh-stiffness loss Σ Δk of the PE table (ratio 1.81) — within 25 %
    (median over orders 4-37; below 4 the speed-ramp residue, above 37 the floor)."""
    g = pair_model(load_config(EXAMPLE), "low").geometry
    t0 = mesh_stiffness(g, n_per_cycle=64, n_cycles=3, n_slices=1)
    loss = []
    for q in (0.15, 0.25):
        crack = Crack(gear="b", tooth=0, depth=q * ROOT_CHORD, angle=math.radians(45.0))
        t = mesh_stiffness(g, n_per_cycle=64, n_cycles=3, n_slices=1, faults=[crack])
        loss.append(float((t0.total - t.total).sum()))
    expected = loss[1] / loss[0]
    r = _gains("crack25", "crack15", range(4, 38))
    assert np.median(r) == pytest.approx(expected, rel=0.25)
    assert np.mean(r > 1.0) >= 0.9
    assert np.median(_gains("crack15", "healthy", range(4, 38))) > 2.0


def _induced(case: str, orders: np.ndarray) -> np.ndarray:
    """Fault-induced amplitude |X_fault(k) − X_healthy(k)| (rad/s) at integer orders k of the
    detrended low-speed shaft IAS (Hann window, same record length): the healthy content
    (mesh orders, ramp residue) cancels, only the once-per-revolution family is left."""
    x, h = detrended(case), detrended("healthy")
    w = np.hanning(x.size)
    d = np.abs(np.fft.rfft(x * w) - np.fft.rfft(h * w)) * 2 / w.sum()
    idx = np.round(orders * x.size / PPR).astype(int)
    return np.array([d[i - 1 : i + 2].max() for i in idx])


def _static_pulse(case: str, orders: np.ndarray) -> np.ndarray:
    """Independent quasi-static reference: |Fourier coefficient| at shaft order k of the static
    transmission error change ΔSTE = F/k_fault − F/k_healthy of the low stage's PE mesh
    stiffness over one wheel revolution (F from 100 N·m on the output)."""
    from ._runs import _variant

    g = pair_model(load_config(EXAMPLE), "low").geometry
    npc = 64
    tabs = {}
    for c in ("healthy", case):
        pm = pair_model(parse_config(_variant(c)), "low")
        tabs[c] = mesh_stiffness(g, n_per_cycle=npc, n_cycles=None, faults=pm.faults).total
    f = 100.0 / g.base_radius[1]
    d = f / tabs[case] - f / tabs["healthy"]
    per_rev = g.b.teeth * npc
    d = d[: (d.size // per_rev) * per_rev].reshape(-1, per_rev).mean(0)
    return np.abs(np.fft.rfft(d)[orders]) / per_rev


def test_fig18_crack_harmonics_sink_faster_than_spall() -> None:
    """Fig 18: "the peaks associated to the crack sink a bit faster into the base noise level …
    for the highest harmonics … the duration of the effect of the crack is of the same order as
    the tooth mesh period, whereas it is shorter for the (modelled) spall". Tested on the ratio
    R(k) of the spall's to the deep crack's fault-induced amplitudes (the system's response,
    common to both, cancels): R rises from orders 4-19 to 38-54, i.e. the crack sinks faster,
    and the rise equals that of the quasi-static ΔSTE pulses (crack 1.61 mesh cycles long,
    spall 0.97) — measured 3.06 against 2.77. The magnitude R ≈ 8 (not "very similar": the
    seed's own Fig 19b finds the spall "more energetic") also equals the quasi-static one: a
    half-face spall removes half of the single pair's stiffness, the 25 % crack 9.4 %.
    Tolerance: 3 standard errors of the band medians of log(R/R_static), from their
    order-to-order scatter (statistics, not chosen)."""
    orders = np.arange(4, 55)
    r = _induced("gear_spall", orders) / _induced("crack25", orders)
    r_static = _static_pulse("gear_spall", orders) / _static_pulse("crack25", orders)
    log_dev = np.log(r / r_static)
    lo, hi, mid = orders < 20, orders >= 38, orders < 38

    def se(x: np.ndarray) -> float:  # standard error of a median
        return 1.2533 * x.std(ddof=1) / np.sqrt(x.size)

    rise = np.median(r[hi]) / np.median(r[lo])
    rise_static = np.median(r_static[hi]) / np.median(r_static[lo])
    assert rise > 1.5 and rise_static > 1.5  # the crack sinks faster
    tol = 3 * np.hypot(se(log_dev[lo]), se(log_dev[hi]))
    assert abs(np.log(rise / rise_static)) < tol
    assert abs(np.median(log_dev[mid])) < 3 * se(log_dev[mid])  # magnitude, orders 4-37
    assert np.median(_gains("crack25", "healthy", range(4, 38))) > 2.0  # both raise the
    assert np.median(_gains("gear_spall", "healthy", range(4, 38))) > 2.0  # integer orders


def test_half_face_spall_halves_the_single_pair_stiffness() -> None:
    """Closed form behind the magnitude: in single-pair contact on the spall (100 µm deep, far
    beyond the ≈ 4 µm mesh deflection, eq 13) the spalled half of the face carries nothing, so
    the mesh stiffness drops by exactly half; the deep crack's largest loss is 9.4 %."""
    from ._runs import _variant

    g = pair_model(load_config(EXAMPLE), "low").geometry
    h = mesh_stiffness(g, n_per_cycle=64, n_cycles=None).total
    loss = {}
    for c in ("gear_spall", "crack25"):
        pm = pair_model(parse_config(_variant(c)), "low")
        loss[c] = float(np.max(1 - mesh_stiffness(g, n_per_cycle=64, n_cycles=None,
                                                  faults=pm.faults).total / h))
    assert loss["gear_spall"] == pytest.approx(0.5, abs=0.01)  # 24 slices: 12 lost
    # regression guard (no source value): the Chen & Shao dead-zone crack of 25 % root chord
    assert loss["crack25"] == pytest.approx(0.094, abs=0.005)


def _rahmonic(case: str) -> float:
    cep = real_cepstrum(detrended(case), float(PPR))
    q, v = cep.quefrency.values, np.abs(cep.values)
    i = int(np.argmin(np.abs(q - 1.0)))
    return float(v[i - 1 : i + 2].max())


def test_fig19_cepstrum_once_per_revolution() -> None:
    """Fig 19: (a) the normal crack makes the one-revolution rahmonic emerge from the healthy
    level; (b) the spall's is more energetic than the deep crack's."""
    h, c15, c25, sp = (_rahmonic(c) for c in ("healthy", "crack15", "crack25", "gear_spall"))
    assert c15 > 1.5 * h
    assert c25 > c15
    assert sp > 2.0 * c25


def _lobes(case: str) -> tuple[int, float, float]:
    """(spacing in samples, first, second impulse) of the revolution-averaged faulty − healthy
    IAS normalised by its maximum: after the onset (first |d| > 10 % of the maximum), the
    first negative lobe deeper than 0.1, and the deepest other negative lobe within 1.5 mesh
    cycles of the onset."""
    d = mean_difference(case)
    d = np.roll(d, PPR // 2 - int(np.argmax(np.abs(d))))
    d = d / np.abs(d).max()
    win = np.abs(d[PPR // 2 - 40 : PPR // 2 + 1]) > 0.1
    i0 = PPR // 2 - 40 + int(np.argmax(win))
    seg = -d[i0 : i0 + int(1.5 * PPR / 55)]
    lobes = [i for i in range(1, seg.size - 1)
             if seg[i] >= seg[i - 1] and seg[i] >= seg[i + 1] and seg[i] > 0.1]
    first = lobes[0]
    second = max(lobes[1:], key=lambda i: seg[i])
    return second - first, float(seg[first]), float(seg[second])


def test_fig20_double_impulse() -> None:
    """Fig 20: once per revolution the difference faulty − healthy shows an impulse when the
    damaged tooth enters contact and a second when the previous pair leaves it, (ε_α − 1) mesh
    cycles later (ε_α = 1.597: 10.9 samples at 1000 per rev on the 55-tooth wheel; ±4); the
    second impulse relative to the first is larger for the spall than for the crack."""
    eps = pair_model(load_config(EXAMPLE), "low").geometry.contact_ratio
    gap, c1, c2 = _lobes("crack25")
    assert gap == pytest.approx((eps - 1) * PPR / 55, abs=4)
    _, s1, s2 = _lobes("gear_spall")
    assert s2 / s1 > 2.0 * (c2 / c1)


def test_fig10_resonance_band_is_a_model_mode() -> None:
    """Fig 10 (ASC): a group of eigenmodes magnifies a band of orders ([35-65] events/rev in the
    seed). Ours: the hump (2-order running median, lines removed) sits at f_i/f_shaft of a
    linearised-model eigenfrequency f_i over the 360-430 rpm ramp, and inside the seed's band.
    Why the docs' bands differ from the seed's: see docs/validation.md (Fig 10 caption vs text,
    the seed's isolated 16-19 order mode needs a ≈ 105-125 Hz mode that our assumed bearing and
    wheel positions do not produce)."""
    o, a = spectrum("healthy")
    sm = median_filter(a, size=int(2 / o[1]) + 1)
    sel = (o > 5) & (o < 54)
    hump = float(o[np.argmax(np.where(sel, sm, 0.0))])
    assert 35.0 <= hump <= 65.0
    f = prepare(build_model(load_config(EXAMPLE))).frequencies_hz
    assert np.any((f / (430 / 60) <= hump) & (hump <= f / (360 / 60)))
