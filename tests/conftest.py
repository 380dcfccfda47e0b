"""Shared test fixtures."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

# pytest-xdist workers run with COLUMNS=80 (set by execnet), a plain pytest run without a
# terminal has none: the CLI honours COLUMNS (geardyn.cli.common) and would wrap its tables and
# paths at 80 columns in one case and at 200 in the other. Tests see the non-terminal width.
os.environ.pop("COLUMNS", None)

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


@pytest.fixture(scope="session")
def examples_dir() -> Path:
    return EXAMPLES
