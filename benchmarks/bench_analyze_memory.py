"""Peak memory of ``geardyn analyze`` on long records (issue 13 target: a 5e7-sample file under
3 GB peak RSS).

Each row runs ``geardyn analyze`` in a subprocess on a synthetic ``.npy`` record (float32, the
order content of the Hammami bench: order 3 + the planetary mesh order 1040/81 of the motor,
plus noise) with a tacho file, and reads the child's peak RSS from
``resource.getrusage(RUSAGE_CHILDREN).ru_maxrss``. Compared, in the same run, with the
straightforward approach a user would write (whole record as float64, ``scipy`` cubic spline
resampling at the angle instants and ``numpy.fft.rfft``), also in a subprocess. Sizes:
``GEARDYN_BENCH_ANALYZE_N`` (comma-separated sample counts; default ``1e6,1e7,5e7``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FS = 50_000.0
RPM = 1498.5
CONFIG = ROOT / "examples" / "hammami_back_to_back.toml"


def _write_record(folder: Path, n: int) -> tuple[Path, Path]:
    """``signal.npy`` (float32, written in blocks) and ``tacho.npy`` (1 pulse/rev)."""
    sig = folder / "signal.npy"
    f_rot = RPM / 60.0
    rng = np.random.default_rng(0)
    out = np.lib.format.open_memmap(sig, mode="w+", dtype=np.float32, shape=(n,))
    block = 1 << 22
    for i in range(0, n, block):
        t = np.arange(i, min(n, i + block)) / FS
        th = 2 * np.pi * f_rot * t
        out[i:i + t.size] = (np.cos(3 * th) + 0.5 * np.cos(1040 / 81 * th)
                             + 0.1 * rng.standard_normal(t.size))
    out.flush()
    del out
    tacho = folder / "tacho.npy"
    np.save(tacho, np.arange(0.0, n / FS, 1.0 / f_rot))
    return sig, tacho


_NAIVE = textwrap.dedent("""
    import sys
    import numpy as np
    from scipy.interpolate import CubicSpline
    x = np.load(sys.argv[1]).astype(float)
    tp = np.load(sys.argv[2])
    fs, spr = float(sys.argv[3]), 256
    t = np.arange(x.size) / fs
    inside = (t >= tp[0]) & (t <= tp[-1])
    ang = CubicSpline(tp, 2 * np.pi * np.arange(tp.size))(t[inside])
    targets = np.arange(0, ang[-1], 2 * np.pi / spr)
    tk = np.interp(targets, ang, t[inside])
    xr = CubicSpline(t[inside], x[inside])(tk)
    spec = np.abs(np.fft.rfft(xr)) / xr.size
""")


_MEASURE = textwrap.dedent("""
    import resource, subprocess, sys
    proc = subprocess.run(sys.argv[1:], capture_output=True, text=True)
    sys.stderr.write((proc.stdout + proc.stderr)[-300:])
    print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, proc.returncode)
""")


def _child_peak(cmd: list[str]) -> tuple[float, float, int, str]:
    """(peak RSS GB, wall time s, exit code, tail of its output) of ``cmd``, run under a fresh
    wrapper process so that ``RUSAGE_CHILDREN`` holds this command only."""
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", _MEASURE, *cmd], capture_output=True,
                          text=True, check=False)
    wall = time.perf_counter() - t0
    try:
        kb, code = (int(v) for v in proc.stdout.split()[-2:])
    except ValueError:
        return float("nan"), wall, -1, proc.stderr[-300:]
    return kb / 1024**2, wall, code, proc.stderr[-300:]


def run() -> list[dict]:
    sizes = [int(float(s)) for s in
             os.environ.get("GEARDYN_BENCH_ANALYZE_N", "1e6,1e7,5e7").split(",")]
    rows: list[dict] = []
    geardyn = [sys.executable, "-c", "import sys; from geardyn.cli import app; app()"]
    for n in sorted(sizes):
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp)
            sig, tacho = _write_record(folder, n)
            cmd = [*geardyn, "analyze", str(sig), "--config", str(CONFIG), "--fs", str(FS),
                   "--tacho", str(tacho), "--reference", "motor", "--out", str(folder / "rep")]
            peak, wall, code, tail = _child_peak(cmd)
            rows.append({"approach": "geardyn analyze", "samples": f"{n:.0e}",
                         "file_MB": round(sig.stat().st_size / 1e6), "peak_RSS_GB": round(peak, 2),
                         "bytes_per_sample": round(peak * 1024**3 / n, 1),
                         "wall_s": round(wall, 1), "target": "< 3 GB at 5e7",
                         "exit": code if code == 0 else f"{code}: {tail}"})
            naive = [sys.executable, "-c", _NAIVE, str(sig), str(tacho), str(FS)]
            peak, wall, code, tail = _child_peak(naive)
            rows.append({"approach": "straightforward (float64, CubicSpline, rfft)",
                         "samples": f"{n:.0e}", "file_MB": round(sig.stat().st_size / 1e6),
                         "peak_RSS_GB": round(peak, 2),
                         "bytes_per_sample": round(peak * 1024**3 / n, 1),
                         "wall_s": round(wall, 1), "target": "",
                         "exit": code if code == 0 else f"{code}: {tail[-120:]}"})
    return rows
