"""Run the benchmarks and print one table per module (``python -m benchmarks [NAME ...]``)."""

from __future__ import annotations

import os

# One-core numbers: keep BLAS from spreading over (and fighting for) the machine's cores. Must be
# set before numpy is first imported.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import importlib  # noqa: E402
import pkgutil  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from rich.console import Console  # noqa: E402
from rich.table import Table  # noqa: E402


def main(argv: list[str]) -> int:
    console = Console(width=None if sys.stdout.isatty() else 160)
    here = Path(__file__).parent
    names = sorted(m.name for m in pkgutil.iter_modules([str(here)]) if m.name.startswith("bench_"))
    wanted = [a if a.startswith("bench_") else f"bench_{a}" for a in argv]
    if wanted:
        unknown = [w for w in wanted if w not in names]
        if unknown:
            console.print(f"unknown benchmark(s) {unknown}; available: {names}")
            return 2
        names = wanted
    for name in names:
        mod = importlib.import_module(f"benchmarks.{name}")
        t0 = time.perf_counter()
        rows = mod.run()
        table = Table(title=f"{name} ({time.perf_counter() - t0:.1f} s)")
        cols: list[str] = []
        for r in rows:
            cols += [c for c in r if c not in cols]
        for c in cols:
            table.add_column(c)
        for r in rows:
            table.add_row(*[_fmt(r.get(c, "")) for c in cols])
        console.print(table)
    return 0


def _fmt(v: object) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
