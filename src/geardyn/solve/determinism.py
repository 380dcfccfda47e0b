"""Same bits whatever the BLAS threads.

A threaded BLAS/LAPACK (OpenBLAS, MKL) splits a matrix product or factorisation by its
thread count, so the rounding of the model set-up (inverse mass matrix, modal damping from
``eigh``, static equilibrium solves) depends on ``OPENBLAS_NUM_THREADS`` and on whatever a
host application set: a run resumed in another process, a sweep case re-run in the driver
(its workers run one BLAS thread) or a test's in-process reference then differ in the last
bits (3e-10 N·m of drive torque on the seed 002 example). The compiled loops use no BLAS;
:func:`single_thread_blas` pins the set-up to one thread (the matrices are ≤ a few hundred
DOFs: the cost is negligible).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def single_thread_blas() -> Iterator[None]:
    """BLAS and LAPACK limited to one thread inside the block (threadpoolctl)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield
