"""A run gives the same bits whatever the BLAS thread count of the calling process
(geardyn.solve.determinism): the FE set-up (inverse mass, modal damping from eigh, static
equilibrium) differed by 3e-10 N·m of drive torque between 1 and 2 OpenBLAS threads, which
broke bit-identical resumes across processes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from geardyn.config.loader import load_config
from geardyn.run import run_simulation

EX = Path(__file__).resolve().parents[2] / "examples"


def _values(ds) -> np.ndarray:  # noqa: ANN001
    return np.concatenate([ds[v].values.ravel() for v in sorted(ds.data_vars)
                           if ds[v].dtype.kind == "f"])


@pytest.mark.parametrize(("name", "kw"), [("seed002_transmission", {"revolutions": 1.0}),
                                          ("planetary_bench_12dof", {"t_end_s": 0.02})])
def test_same_bits_with_one_or_two_blas_threads(name: str, kw: dict) -> None:
    if not any(i.get("user_api") == "blas" for i in threadpool_info()):
        pytest.skip("no BLAS thread pool found")
    cfg = load_config(EX / f"{name}.toml")
    runs = []
    for threads in (1, 2):
        with threadpool_limits(limits=threads, user_api="blas"):
            got = max(i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas")
            if got != threads:
                pytest.skip(f"BLAS runs {got} thread(s) when asked for {threads}")
            runs.append(_values(run_simulation(cfg, **kw)))
    assert np.array_equal(runs[0], runs[1], equal_nan=True)
