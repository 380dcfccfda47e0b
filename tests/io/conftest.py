"""A short simulated run (seed 004 reclaimer, sun crack; ring accelerometer at 5 kHz) written by
each format's own writer."""

from __future__ import annotations

import numpy as np
import pytest

import geardyn
from tests.conftest import EXAMPLES

#: 100 mV/g: the file holds volts, the record m/s² (g = 9.80665 m/s², ISO 80000-3).
SENS_V_PER_MS2 = 0.1 / 9.80665
MAPPING = """
[measurement]
min_revolutions = 1.0
[[measurement.channels]]
name = "ring_acc"
source = "{source}"
location = "ring"
sensitivity = "100 mV/g"
{extra}
"""


@pytest.fixture(scope="session")
def sim_run():
    """(config, result) of a 2 s run of examples/seed004_diagnose_sun_crack.toml (seed 100)."""
    from geardyn.run import run_simulation

    cfg = geardyn.load_config(EXAMPLES / "seed004_diagnose_sun_crack.toml")
    return cfg, run_simulation(cfg, seed=100, t_end_s=2.0)


def mapped_config(tmp_path, source: str, extra: str = "", base: str =
                  "seed004_diagnose_sun_crack.toml"):
    """The example config plus a [measurement] mapping of the ring accelerometer."""
    p = tmp_path / "measured.toml"
    p.write_text((EXAMPLES / base).read_text() + MAPPING.format(source=source, extra=extra))
    return geardyn.load_config(p)


def analog_tacho(t: np.ndarray, angle: np.ndarray, ppr: int, high: float = 5.0) -> np.ndarray:
    """A TTL pulse train: high during the first half of each of the ``ppr`` periods per
    revolution of ``angle`` [rad]; rising edges at angle = 2πk/ppr. The first sample is low
    (the train starts with an edge)."""
    x = np.where(np.mod(ppr * angle / (2 * np.pi), 1.0) < 0.5, high, 0.0)
    x[0] = 0.0
    return x
