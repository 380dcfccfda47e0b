"""Long records piece by piece (geardyn.signal.stream): the stretch-by-stretch angular
resampling gives the samples of resample_to_angle over the whole record, and the batched
per-revolution statistics those of one pass over all revolutions."""

from __future__ import annotations

import numpy as np
import pytest

import geardyn.signal.stream as stream
from geardyn.signal.resample import resample_to_angle
from geardyn.signal.stream import AngleGrid, RevolutionStats, revolution_spectra

FS = 50_000.0


def _record(n=300_000, seed=0):
    t = np.arange(n) / FS
    angle = 2 * np.pi * (10 * t + 0.3 * t**2) + 0.7  # accelerating shaft
    return np.random.default_rng(seed).standard_normal(n), angle


@pytest.mark.parametrize("spr, ratio", [(8192, 1.0), (2048, 1.0), (16800, 23 / 47),
                                        (4096, 23 / 47)])
def test_grid_stretches_equal_the_whole_record_resampling(spr, ratio):
    """Without (8192, 16800) and with (2048, 4096: cut-off below fs/2) the anti-aliasing
    filter, whole-record filter: the same values, instants and valid order range."""
    x, angle = _record()
    whole = resample_to_angle(x, FS, ratio * angle, samples_per_rev=spr)
    g = AngleGrid(x, FS, angle, spr, ratio=ratio)
    y = np.concatenate([c for _, c in g.chunks(size=70_001)])
    assert g.filtered == (spr in (2048, 4096))
    assert y.size == whole.x.size and g.angle0 == pytest.approx(whole.angle0, rel=1e-15)
    assert np.max(np.abs(y - whole.x)) <= 1e-12 * np.max(np.abs(whole.x))
    assert np.array_equal(g.times(0, g.size), whole.time)
    assert g.max_valid_order == whole.max_valid_order


def test_float32_channel_and_stretched_filter(monkeypatch):
    """A float32 channel is converted stretch by stretch; a record too long to filter whole is
    low-passed stretch by stretch with the settling overlap (agrees to 1e-9 of the signal)."""
    x, angle = _record(seed=1)
    x32 = x.astype(np.float32)
    whole = resample_to_angle(x32.astype(float), FS, angle, samples_per_rev=2048)
    monkeypatch.setattr(stream, "WHOLE_FILTER_MAX", 1000)
    g = AngleGrid(x32, FS, angle, 2048)
    assert g._xf is None and g.filtered
    y = np.concatenate([c for _, c in g.chunks(size=50_000)])
    assert np.max(np.abs(y - whole.x)) <= 1e-9 * np.max(np.abs(whole.x))


def test_revolution_stats_in_batches_equal_one_pass():
    """Chan–Golub–LeVeque pairwise update: mean and ddof-1 variance of the revolutions'
    spectra from batches and merges equal those of one pass (1e-12)."""
    rng = np.random.default_rng(2)
    spr, n = 64, 37
    x = np.cos(2 * np.pi * 5 * np.arange(n * spr) / spr) + rng.normal(0, 0.3, n * spr)
    spec = revolution_spectra(x, spr)
    a, b = RevolutionStats(), RevolutionStats()
    for r0, r1 in ((0, 5), (5, 6), (6, 20)):
        a.add_spectra(spec[r0:r1])
    b.add_spectra(spec[20:])
    a.merge(b)
    mean = spec.mean(axis=0)
    var = np.sum(np.abs(spec - mean) ** 2, axis=0) / (n - 1)
    assert a.n == n
    np.testing.assert_allclose(a.mean, mean, rtol=0, atol=1e-12 * np.abs(mean).max())
    np.testing.assert_allclose(a.var, var, rtol=1e-12)
    np.testing.assert_allclose(a.tsa(spr), x.reshape(n, spr).mean(axis=0), atol=1e-12)
