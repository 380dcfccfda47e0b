"""Start-up time of the package and the CLI (issue 13 item 5 targets: ``import geardyn``
≤ 0.5 s, ``geardyn --help`` well under a second).

Each row is the median wall time of 5 fresh interpreters (subprocess). Compared with the eager
imports the package had before (config + kinematics with pandas, plotting with xarray: what
``import geardyn`` used to load) and with a bare interpreter.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
REPEATS = 5

CLI = "import sys; from geardyn.cli import app; sys.argv[0] = 'geardyn'; app()"

CASES = [
    ("python (bare interpreter)", [sys.executable, "-c", "pass"], ""),
    ("import geardyn", [sys.executable, "-c", "import geardyn"], "≤ 0.5 s"),
    ("eager imports (before: config, kinematics/pandas, plotting/xarray)",
     [sys.executable, "-c", "import geardyn.config, geardyn.kinematics, geardyn.plotting"], ""),
    ("geardyn --help", [sys.executable, "-c", CLI, "--help"], "well under 1 s"),
    ("geardyn simulate --help", [sys.executable, "-c", CLI, "simulate", "--help"], ""),
    ("geardyn --version", [sys.executable, "-c", CLI, "--version"], ""),
    ("geardyn kinematics car_differential.toml",
     [sys.executable, "-c", CLI, "kinematics", str(ROOT / "examples" / "car_differential.toml")],
     ""),
]


def _median_wall(cmd: list[str]) -> tuple[float, int]:
    times = []
    code = 0
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, check=False)
        times.append(time.perf_counter() - t0)
        code = code or proc.returncode
    return statistics.median(times), code


def run() -> list[dict]:
    rows = []
    for name, cmd, target in CASES:
        wall, code = _median_wall(cmd)
        rows.append({"command": name, "median_s": round(wall, 3), "target": target,
                     "exit": code})
    return rows
