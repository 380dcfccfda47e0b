from __future__ import annotations

from pathlib import Path

import pytest

from geardyn.config.loader import load_config
from geardyn.models.planetary.build import model_from_config

EX = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="session")
def bench36():
    return model_from_config(load_config(EX / "planetary_bench_36dof.toml"))


@pytest.fixture(scope="session")
def bench12():
    return model_from_config(load_config(EX / "planetary_bench_12dof.toml"))


@pytest.fixture(scope="session")
def lin_parker():
    return model_from_config(load_config(EX / "planetary_lin_parker.toml"))
