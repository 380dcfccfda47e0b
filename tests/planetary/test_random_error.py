"""Seed 004 §4.1.3 random impulse excitation: distribution and reproducibility."""

from __future__ import annotations

import copy
import math
import tomllib

import numpy as np
import pytest

from geardyn.config import parse_config
from geardyn.models.planetary.build import mesh_laws, model_from_config, random_impulses

from .conftest import EX


def test_impulse_distribution_matches_the_thesis_draw():
    # thesis: randint([−400, 100]) → impulse with probability 100/501, uniform up to 1e−3 mm
    n = 200_000
    e = random_impulses(n, 1e-6, 100 / 501, 7)
    hit = e > 0
    p = 100 / 501
    assert hit.mean() == pytest.approx(p, abs=4 * math.sqrt(p * (1 - p) / n))
    assert e.max() <= 1e-6
    assert e[hit].mean() == pytest.approx(0.5e-6, rel=0.02)  # uniform (0, max]
    np.testing.assert_array_equal(e, random_impulses(n, 1e-6, p, 7))
    assert not np.array_equal(e, random_impulses(n, 1e-6, p, 8))


def _laws(raw, **stage):
    d = copy.deepcopy(raw)
    d["planetary_dynamics"]["stages"][0].update(stage)
    cfg = parse_config(d)
    return mesh_laws(cfg, model_from_config(cfg))


def test_random_errors_enter_every_planet_mesh_independently():
    with open(EX / "planetary_reclaimer.toml", "rb") as fh:
        raw = tomllib.load(fh)
    base = _laws(raw, faults=[], transmission_error=True)
    rnd = _laws(raw, faults=[], transmission_error=True, random_error_max_m=1e-6)
    again = _laws(raw, faults=[], transmission_error=True, random_error_max_m=1e-6)
    for key, law in rnd.items():
        b = base[key]
        for pl, (_, _, err, _) in law.per_planet.items():
            extra = err - b.per_planet[pl][2] if b.per_planet else err - b.e
            assert (extra >= 0).all() and extra.max() <= 1e-6
            assert 0.15 < (extra > 0).mean() < 0.25
            np.testing.assert_array_equal(err, again[key].per_planet[pl][2])
        e1, e2 = law.per_planet[1][2], law.per_planet[2][2]
        assert not np.array_equal(e1, e2)  # independent sequences per planet mesh
