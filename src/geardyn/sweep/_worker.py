"""Preload of the LocalCluster workers (``distributed.worker.preload``): a worker process
ignores SIGINT, so that Ctrl-C in the terminal — sent to the whole process group — stops the
driver only; the driver then cancels the cases and closes the cluster itself."""

from __future__ import annotations

import signal
import threading
from typing import Any


def dask_setup(worker: Any) -> None:  # noqa: ARG001 - dask preload hook
    """Ignore SIGINT in this worker process (main thread only: signal handlers live there)."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
