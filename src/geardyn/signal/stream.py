"""Long records piece by piece: angular resampling of any stretch of a uniform angle grid and
per-revolution spectral statistics, without record-long intermediate arrays.

:class:`AngleGrid` gives the samples of :func:`geardyn.signal.resample_to_angle` (the same
anti-aliasing rule, angle → time inversion and windowed-sinc kernel, called on one stretch of
the record at a time) for any range of grid indices; the channel stays as stored (a float32
channel is converted stretch by stretch). Records up to :data:`WHOLE_FILTER_MAX` samples that
need the anti-aliasing filter are filtered whole (the values of ``resample_to_angle``); longer
ones stretch by stretch with an overlap in which the zero-phase filter settles
(:func:`_settle`).

:class:`RevolutionStats` accumulates the mean and the variance (ddof = 1) of per-revolution
spectra in batches with the pairwise update of Chan, Golub & LeVeque (1979, "Updating formulae
and a pairwise algorithm for computing sample variances"), so that the synchronous average
(seed 003 eq 1.25) and its revolution-to-revolution variance (Braun 1975) of any number of
revolutions cost one revolution batch of memory.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
from scipy import signal as sps

from geardyn.errors import InputError
from geardyn.signal.resample import (
    _SINC_PHASES,
    _SINC_SLOPES,
    SINC_HALF_WIDTH,
    SINC_PASSBAND,
    SINC_TABLE_DENSITY,
    AngleSignal,
    _sinc_interp,
    lowpass,
)

TWO_PI = 2.0 * np.pi
#: Grid samples computed per stretch (8 MB of float64).
CHUNK = 1 << 20
#: Longest record (samples) low-passed whole when the anti-aliasing filter is needed.
WHOLE_FILTER_MAX = 1 << 22


def _settle(fs: float, cutoff: float) -> int:
    """Samples over which the zero-phase 8th-order Butterworth low-pass at ``cutoff`` settles to
    1e-12: its slowest pole decays at ``2π·f_c·sin(π/16)`` [1/s] (Butterworth poles on a circle
    of radius ``2π·f_c``), i.e. by e^−27.6 within ``45·fs/f_c`` samples; doubled for the
    bilinear warping near Nyquist."""
    return int(90.0 * fs / cutoff) + 64


class AngleGrid:
    """Uniform angle grid of a uniformly time-sampled channel, computed stretch by stretch.

    ``x``: samples at ``fs`` [Hz] from ``t0`` [s] (any float dtype, kept as given);
    ``angle``: the reference angle [rad] at each sample, strictly increasing; the grid is in the
    own angle ``ratio·angle`` (``ratio`` > 0): grid point ``k`` is at own angle
    ``k·2π/samples_per_rev``, ``k0 … k1`` those inside the record. Same anti-aliasing as
    :func:`geardyn.signal.resample_to_angle` (cut-off ``f_rot,min·spr/2.56`` when below
    ``fs/2``; ``max_valid_order`` likewise)."""

    def __init__(self, x: np.ndarray, fs: float, angle: np.ndarray, samples_per_rev: int,
                 t0: float = 0.0, anti_alias: bool = True, ratio: float = 1.0) -> None:
        if x.ndim != 1 or angle.shape != x.shape:
            raise InputError(f"angle: need one angle per sample of x ({x.size}), got "
                             f"{angle.size}")
        self.x, self.fs, self.angle, self.t0 = x, float(fs), angle, float(t0)
        self.ratio = float(ratio)
        self.samples_per_rev = spr = int(samples_per_rev)
        n = x.size
        d_min, d_max = math.inf, 0.0
        for a in range(0, n - 1, CHUNK):
            d = np.diff(self.ratio * angle[a:a + CHUNK + 1])
            d_min, d_max = min(d_min, float(d.min())), max(d_max, float(d.max()))
        if not d_min > 0:
            raise InputError("angle: the reference angle must be strictly monotonic (the shaft "
                             "must not stop or reverse during the record)")
        f_min, f_max = d_min * fs / TWO_PI, d_max * fs / TWO_PI
        self.rate_min, self.rate_max = f_min, f_max
        self.cutoff = f_min * spr / 2.56
        self.max_valid_order = min(0.8 * self.cutoff, SINC_PASSBAND * fs) / f_max
        self.filtered = anti_alias and self.cutoff < 0.5 * fs
        self._xf = None
        if self.filtered:
            self._sos = sps.butter(8, self.cutoff, btype="low", fs=fs, output="sos")
            if n <= WHOLE_FILTER_MAX:
                self._xf = lowpass(np.asarray(x, dtype=float), fs, self.cutoff)
        dth = TWO_PI / spr
        self.k0 = int(np.ceil(self.ratio * angle[0] / dth))
        self.k1 = int(np.floor(self.ratio * angle[-1] / dth))
        if self.k1 - self.k0 < 4:
            raise InputError("angle: the record spans fewer than 4 angular samples")

    @property
    def size(self) -> int:
        """Grid points inside the record."""
        return self.k1 - self.k0 + 1

    @property
    def angle0(self) -> float:
        return self.k0 * TWO_PI / self.samples_per_rev

    def _source(self, lo: int, hi: int) -> np.ndarray:
        """Samples ``lo:hi`` of the (low-passed) channel as float64."""
        if not self.filtered:
            return np.asarray(self.x[lo:hi], dtype=float)
        if self._xf is not None:
            return self._xf[lo:hi]
        m = _settle(self.fs, self.cutoff)
        a, b = max(0, lo - m), min(self.x.size, hi + m)
        return sps.sosfiltfilt(self._sos, np.asarray(self.x[a:b], dtype=float))[lo - a:hi - a]

    def times(self, a: int, b: int) -> np.ndarray:
        """Instants [s] of grid samples ``a … b−1`` (counted from ``k0``)."""
        targets = (TWO_PI / self.samples_per_rev) * np.arange(self.k0 + a, self.k0 + b)
        r = self.ratio
        i = max(0, int(np.searchsorted(self.angle, targets[0] / r, side="right")) - 2)
        j = min(self.x.size, int(np.searchsorted(self.angle, targets[-1] / r, side="left")) + 2)
        t = self.t0 + np.arange(i, j) / self.fs
        u = self.angle[i:j] if r == 1.0 else r * self.angle[i:j]
        return np.interp(targets, u, t)

    def samples(self, a: int, b: int) -> np.ndarray:
        """Grid samples ``a … b−1`` (counted from ``k0``; float64) — those of
        :func:`geardyn.signal.resample_to_angle` over the whole record."""
        if not 0 <= a < b <= self.size:
            raise InputError(f"grid: samples {a}…{b} outside 0…{self.size}")
        pos = (self.times(a, b) - self.t0) * self.fs
        lo = max(0, int(np.floor(pos[0])) - SINC_HALF_WIDTH - 1)
        hi = min(self.x.size, int(np.floor(pos[-1])) + SINC_HALF_WIDTH + 2)
        return _sinc_interp(np.ascontiguousarray(self._source(lo, hi)), pos - lo, _SINC_PHASES,
                            _SINC_SLOPES, SINC_TABLE_DENSITY)

    def chunks(self, a: int = 0, b: int | None = None, size: int = CHUNK
               ) -> Iterator[tuple[int, np.ndarray]]:
        """``(start, samples)`` of consecutive stretches of grid samples ``a … b−1``."""
        b = self.size if b is None else b
        for s in range(a, b, size):
            yield s, self.samples(s, min(b, s + size))

    def signal(self, a: int = 0, b: int | None = None) -> AngleSignal:
        """Grid samples ``a … b−1`` as an :class:`~geardyn.signal.resample.AngleSignal`."""
        b = self.size if b is None else b
        return AngleSignal(self.samples(a, b), self.samples_per_rev,
                           (self.k0 + a) * TWO_PI / self.samples_per_rev, self.times(a, b),
                           self.max_valid_order)


class ArrayGrid:
    """An :class:`AngleSignal` held whole, with the interface of :class:`AngleGrid`."""

    def __init__(self, sig: AngleSignal) -> None:
        self.sig = sig
        self.samples_per_rev = sig.samples_per_rev
        self.k0 = int(round(sig.angle0 / (TWO_PI / sig.samples_per_rev)))
        self.max_valid_order = sig.max_valid_order

    @property
    def size(self) -> int:
        return self.sig.x.size

    @property
    def angle0(self) -> float:
        return self.sig.angle0

    def samples(self, a: int, b: int) -> np.ndarray:
        return self.sig.x[a:b]

    def chunks(self, a: int = 0, b: int | None = None, size: int = CHUNK
               ) -> Iterator[tuple[int, np.ndarray]]:
        b = self.size if b is None else b
        for s in range(a, b, size):
            yield s, self.sig.x[s:min(b, s + size)]


class RevolutionStats:
    """Mean and variance (ddof = 1) of per-revolution rfft spectra (orders 0 … spr/2),
    accumulated batch by batch (module docstring)."""

    def __init__(self) -> None:
        self.n = 0
        self.mean: np.ndarray | None = None
        self.m2: np.ndarray | None = None

    def add_spectra(self, spec: np.ndarray) -> None:
        """Add revolutions given by their spectra (rows)."""
        nb = spec.shape[0]
        if nb == 0:
            return
        mb = spec.mean(axis=0)
        m2b = np.sum(np.abs(spec - mb) ** 2, axis=0)
        if self.n == 0:
            self.n, self.mean, self.m2 = nb, mb, m2b
            return
        n = self.n + nb
        delta = mb - self.mean
        self.mean = self.mean + delta * (nb / n)
        self.m2 = self.m2 + m2b + np.abs(delta) ** 2 * (self.n * nb / n)
        self.n = n

    def merge(self, other: RevolutionStats) -> None:
        """Add another accumulation (disjoint revolutions)."""
        if other.n == 0:
            return
        if self.n == 0:
            self.n, self.mean, self.m2 = other.n, other.mean.copy(), other.m2.copy()
            return
        n = self.n + other.n
        delta = other.mean - self.mean
        self.mean = self.mean + delta * (other.n / n)
        self.m2 = self.m2 + other.m2 + np.abs(delta) ** 2 * (self.n * other.n / n)
        self.n = n

    @property
    def var(self) -> np.ndarray:
        """Variance of the revolutions' spectra per order (ddof = 1; zeros for one)."""
        return self.m2 / (self.n - 1) if self.n > 1 else np.zeros_like(self.m2)

    def tsa(self, samples_per_rev: int) -> np.ndarray:
        """The synchronous average (one revolution)."""
        return np.fft.irfft(self.mean, samples_per_rev)


def revolution_spectra(x: np.ndarray, samples_per_rev: int) -> np.ndarray:
    """rfft of each whole revolution of ``x`` (rows)."""
    n = x.size // samples_per_rev
    return np.fft.rfft(x[: n * samples_per_rev].reshape(n, samples_per_rev), axis=1)


__all__ = ["CHUNK", "AngleGrid", "ArrayGrid", "RevolutionStats", "revolution_spectra"]
