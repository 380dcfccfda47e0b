"""First ``geardyn simulate`` on an empty numba cache, and after the install-time warm-up.

Each case runs in a fresh subprocess with ``NUMBA_CACHE_DIR`` pointing to its own temporary
directory (numba then neither reads nor writes the cache next to the sources):

1. cold: ``geardyn simulate examples/planetary_reclaimer.toml`` (seed 004, 0.05 s) on the
   empty cache: imports, model build, compilation of every kernel the run needs, the run, the
   NetCDF write;
2. the warm-up ``python -m geardyn.warmup`` (what ``make`` runs after the install) on another
   empty cache;
3. the same ``geardyn simulate`` on the cache the warm-up filled (target ≤ 5 s);
4. the same once more (the cache is warm either way: imports and run only).

Wall and CPU time (user + system of the child) are given: the machine is shared, so the CPU
time is the figure that does not depend on the load (printed with ``os.getloadavg``).
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples" / "planetary_reclaimer.toml"
TARGET_S = 5.0


def _child(args: list[str], cache: str) -> tuple[float, float]:
    """(wall s, CPU s) of ``python args`` in a subprocess with NUMBA_CACHE_DIR = ``cache``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": cache}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, *args], cwd=ROOT, env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def run() -> list[dict]:
    simulate = ["-c", "from geardyn.cli import app; app(prog_name='geardyn')", "simulate",
                str(EX), "--force", "--out"]
    rows: list[dict] = []
    with tempfile.TemporaryDirectory() as tmp:
        out = str(Path(tmp) / "run.nc")
        cold, warm = str(Path(tmp) / "cold"), str(Path(tmp) / "warm")
        w, c = _child(simulate + [out], cold)
        rows.append({"case": "geardyn simulate (reclaimer, 0.05 s), empty numba cache",
                     "wall_s": w, "cpu_s": c, "target": f"≤ {TARGET_S:g} s",
                     "met": c <= TARGET_S, "load": f"{os.getloadavg()[0]:.1f}"})
        w, c = _child(["-m", "geardyn.warmup"], warm)
        rows.append({"case": "python -m geardyn.warmup (make's install step), empty cache",
                     "wall_s": w, "cpu_s": c, "target": "", "met": "",
                     "load": f"{os.getloadavg()[0]:.1f}"})
        for label in ("first geardyn simulate after the warm-up", "second geardyn simulate"):
            w, c = _child(simulate + [out], warm)
            rows.append({"case": label, "wall_s": w, "cpu_s": c,
                         "target": f"≤ {TARGET_S:g} s" if label.startswith("first") else "",
                         "met": c <= TARGET_S if label.startswith("first") else "",
                         "load": f"{os.getloadavg()[0]:.1f}"})
    return rows
