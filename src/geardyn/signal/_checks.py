"""Input validation shared by the signal and sensor modules.

Every check raises :class:`geardyn.errors.InputError` naming the argument and the rule, so that
bad input never surfaces as a deep numpy traceback or a silently wrong result.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from geardyn.errors import InputError


def positive(name: str, value: Any, what: str = "") -> float:
    """Return ``value`` as a finite float > 0, else raise ``InputError``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: {what or 'value'} must be a number > 0, got {value!r}") from None
    if not np.isfinite(v) or v <= 0:
        raise InputError(f"{name}: {what or 'value'} must be > 0, got {value!r}")
    return v


def positive_int(name: str, value: Any, what: str = "", minimum: int = 1) -> int:
    """Return ``value`` as an int >= ``minimum``, else raise ``InputError``."""
    try:
        v = int(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: {what or 'value'} must be an integer, got {value!r}") from None
    if v != value and not (isinstance(value, float) and float(v) == value):
        raise InputError(f"{name}: {what or 'value'} must be an integer, got {value!r}")
    if v < minimum:
        raise InputError(f"{name}: {what or 'value'} must be >= {minimum}, got {value!r}")
    return v


def array1d(name: str, value: Any, min_len: int = 1, what: str = "") -> np.ndarray:
    """Return ``value`` as a finite 1-D float array with at least ``min_len`` samples."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: {what or 'signal'} must be a 1-D array of numbers") from None
    if a.ndim != 1:
        raise InputError(f"{name}: {what or 'signal'} must be 1-D, got shape {a.shape}")
    if a.size < min_len:
        raise InputError(
            f"{name}: {what or 'signal'} needs at least {min_len} samples, got {a.size}"
        )
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name}: {what or 'signal'} contains NaN or infinite values")
    return a


def increasing(name: str, a: np.ndarray, what: str = "values") -> None:
    """Raise unless ``a`` is strictly increasing."""
    if a.size > 1 and not np.all(np.diff(a) > 0):
        raise InputError(f"{name}: {what} must be strictly increasing")


def rng(seed: int | np.random.Generator | None, name: str = "seed") -> np.random.Generator:
    """Every random draw takes a seed: ``None`` is refused."""
    if seed is None:
        raise InputError(f"{name}: a seed (int or numpy Generator) is required for random draws")
    if isinstance(seed, np.random.Generator):
        return seed
    return np.random.default_rng(positive_int(name, seed, "seed", minimum=0))


def planet_angles(value: Any, n: int) -> np.ndarray:
    """Planet angles [rad]: ``value`` (one per planet) or, if ``None``, equally spaced 2πk/n."""
    if value is None:
        return 2.0 * np.pi * np.arange(n) / n
    psi = array1d("planet_angles", value, 1, "planet angles [rad]")
    if psi.size != n:
        raise InputError(f"planet_angles: needs {n} angles (one per planet), got {psi.size}")
    return psi
