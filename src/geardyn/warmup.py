"""Compile and cache every numba kernel once, with tiny inputs (``python -m geardyn.warmup``).

The kernels are compiled with ``cache=True``: numba writes the machine code next to the sources
(``__pycache__``, or ``NUMBA_CACHE_DIR`` when set) and later processes load it in milliseconds
instead of compiling for seconds. ``make run``/``make test`` call this module right after the
install, so that the first ``geardyn simulate`` does not pay the compilation.

The kernels are reached through the same public paths as real runs (the ``planetary`` and
``transmission`` starter templates through :func:`geardyn.run.run_simulation`, short runs), so
that the argument types, and with them the cached signatures, are those of real runs; the
variants a template does not reach (dense step solve with gyroscopic terms, the low-rank solver
of :mod:`geardyn.solve.lowrank`, the compiled right-hand side of ``adaptive``, the resampling
of :mod:`geardyn.signal.resample`) are called directly on a small synthetic system.
"""

from __future__ import annotations

import sys
import tempfile
import time
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np


def _templates() -> None:
    from geardyn.config.loader import load_config
    from geardyn.run import run_simulation
    from geardyn.templates import render

    with tempfile.TemporaryDirectory() as tmp:
        for name, kw in (("planetary", {"t_end_s": 2e-3}), ("transmission", {"revolutions": 0.02})):
            path = Path(tmp) / f"{name}.toml"
            path.write_text(render(name, path.name))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                run_simulation(load_config(path), **kw)


def small_system(gyro: bool = False):  # noqa: ANN201
    """A 4-DOF system with two meshes (one with contact loss), every drive kind, a mass
    schedule and optionally gyroscopic terms (types as built by the model builders)."""
    from geardyn.solve.integrate import Drives, LinearSystem, MassSchedule, VarSprings

    n = 4
    m = np.diag([1.0, 2.0, 1.5, 3.0])
    k = np.diag([0.0, 1e4, 2e4, 1e4])
    c = 1e-4 * k + np.diag([0.1, 0.0, 0.0, 0.0])
    springs = VarSprings.build([
        {"a": [1.0, -1.0, 0, 0], "b": [1.0, 0, 0, 0], "k": [1e5, 2e5], "e": [0.0, 1e-6],
         "c": 1.0},
        {"a": [0, 1.0, -1.0, 0], "b": [0, 1.0, 0, 0], "k": [1e5], "contact_loss": True},
    ], n)
    drives = Drives.build([
        {"kind": 0, "a": 0, "x": [0.0, 10.0], "y": [5.0, 0.0]},
        {"kind": 1, "a": 0, "b": 1, "p0": 0.01, "p1": 1.0},
        {"kind": 2, "a": 3, "p0": 0.01, "x": [0.0, 1.0], "y": [1.0, 1.0]},
        {"kind": 3, "a": 2, "p0": 10.0, "p1": 1.0, "x": [0.0, 1.0], "y": [0.0, 1.0]},
    ])
    sched = MassSchedule(np.array([3], np.int64), np.array([3], np.int64), np.array([1.0]),
                         np.array([[0.0, 1.0]]), np.array([[3.0, 3.5]]),
                         np.array([2], np.int64))
    sys_ = LinearSystem(m, c, k, springs, drives, np.array([0.0, 1.0]), np.zeros((2, n)),
                        sched, [f"q{i}" for i in range(n)])
    if gyro:
        g = np.zeros((1, n, n))
        g[0, 1, 2], g[0, 2, 1] = 50.0, -50.0
        sys_.gyro_g, sys_.gyro_k = g, np.abs(g)
        sys_.gyro_rate = np.array([[1.0, 0.0, 0.0, 0.0]])
    return sys_


def _solvers() -> None:
    from geardyn.solve.integrate import adaptive, newmark
    from geardyn.solve.lowrank import newmark_lowrank

    q0 = np.zeros(4)
    v0 = np.array([1.0, 1.0, 1.0, 1.0])
    for gyro, solve in ((False, "lowrank"), (True, "dense")):
        newmark(small_system(gyro), q0, v0, 1e-3, 1e-4, solve=solve)
    plain = small_system()
    plain.mass_schedule = type(plain.mass_schedule)()
    newmark_lowrank(plain, q0, v0, 1e-3, 1e-4)
    adaptive(plain, q0, v0, np.array([0.0, 1e-4]))


def _signal() -> None:
    from geardyn.signal.resample import resample_to_angle

    fs = 1000.0
    t = np.arange(256) / fs
    resample_to_angle(np.sin(2 * np.pi * 50 * t), fs, angle=2 * np.pi * 10 * t,
                      samples_per_rev=16)


STEPS: tuple[tuple[str, Callable[[], None]], ...] = (
    ("planetary and transmission templates", _templates),
    ("solver variants", _solvers),
    ("signal resampling", _signal),
)


def main() -> int:
    """Run every warm-up step, printing its time; returns the exit code."""
    t0 = time.perf_counter()
    for label, step in STEPS:
        t = time.perf_counter()
        step()
        print(f"warm-up: {label} compiled/loaded in {time.perf_counter() - t:.1f} s")
    print(f"warm-up: done in {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
