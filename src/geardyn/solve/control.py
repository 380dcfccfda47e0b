"""Control of a long integration run cut into chunks: progress, stop requests, checkpoints.

The compiled integration loops (:func:`geardyn.solve.integrate.newmark`, the FE transmission
loop) advance the state by one chunk of steps, then return to Python, where a
:class:`RunControl` reports progress, honours a stop request (Ctrl-C / SIGTERM caught by the
caller, see :mod:`geardyn.checkpoint`) and hands the integrator state to a checkpoint writer
when the wall-clock interval has passed. Chunking is exact: the state carried between chunks is
the complete state of the loop, so a chunked (or resumed) run gives the same bytes as one call.

Chunk sizes follow the measured cost per step: two short chunks (the first loads the compiled
code, the second measures the cost per step), then chunks of about
:attr:`RunControl.chunk_wall_s` seconds. After the second chunk the total cost is estimated and
passed to ``estimate`` (seconds), so that a long run announces its duration before it goes on.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from geardyn.errors import InputError

#: Steps of the first (warm-up) chunk.
WARMUP_STEPS = 400


@dataclass
class RunControl:
    """Progress, stop and checkpoint hooks of a chunked run (all optional).

    ``progress(fraction)``: called after every chunk. ``estimate(seconds)``: called once, after
    the warm-up chunk, with the estimated wall time of the whole run. ``checkpoint(state)``:
    called with the integrator state (a dict of arrays and numbers) every
    ``checkpoint_every_s`` seconds of wall-clock time, and once more when a stop request ends
    the run early. ``resume``: a state returned by an earlier checkpoint, to continue from.
    """

    progress: Callable[[float], None] | None = None
    estimate: Callable[[float], None] | None = None
    checkpoint: Callable[[dict], None] | None = None
    checkpoint_every_s: float = 0.0
    resume: dict | None = None
    chunk_wall_s: float = 0.25
    stop_requested: bool = False
    stop_reason: str = ""
    _last_checkpoint: float = field(default_factory=time.monotonic)
    _step_cost_s: float = 0.0
    _chunks: int = 0
    _estimated: bool = False

    def request_stop(self, reason: str = "interrupted") -> None:
        """Ask the running loop to stop after the current chunk (safe from a signal handler)."""
        self.stop_requested = True
        self.stop_reason = reason

    def next_chunk(self, done: int, total: int, max_steps: int | None = None) -> int:
        """Steps of the next chunk: the warm-up first, then about ``chunk_wall_s`` of work."""
        left = total - done
        if self._chunks < 2:
            n = WARMUP_STEPS
        else:
            n = max(WARMUP_STEPS, int(self.chunk_wall_s / self._step_cost_s))
        if max_steps is not None:
            n = min(n, max_steps)
        return max(1, min(n, left))

    def chunk_done(self, steps: int, wall_s: float, done: int, total: int,
                   state: Callable[[], dict]) -> None:
        """Book a finished chunk: cost per step, estimate, progress, checkpoint if due."""
        self._chunks += 1
        # the first chunk includes loading the compiled code: the cost is measured from the
        # second one on (the smallest seen, as other processes share the machine)
        if self._chunks >= 2 and steps > 0 and wall_s > 0.0:
            cost = wall_s / steps
            self._step_cost_s = cost if self._step_cost_s <= 0.0 else min(cost,
                                                                           self._step_cost_s)
        if not self._estimated and self._step_cost_s > 0.0 and done < total:
            self._estimated = True
            if self.estimate is not None:
                self.estimate(self._step_cost_s * total)
        if self.progress is not None:
            self.progress(done / total if total else 1.0)
        if self.checkpoint is not None and done < total and (
                self.stop_requested or (self.checkpoint_every_s > 0.0 and time.monotonic()
                                        - self._last_checkpoint >= self.checkpoint_every_s)):
            self.checkpoint(state())
            self._last_checkpoint = time.monotonic()


def drive_chunks(ctl: RunControl, done: int, total: int,
                 advance: Callable[[int, int], tuple[int, int]],
                 state: Callable[[int], dict]) -> tuple[int, int]:
    """The chunk loop shared by the FE integrators (explicit, Newmark, modal): advance
    ``done`` → ``total`` steps (or ticks) in chunks sized by ``ctl``, ``advance(start, stop)``
    returning (step reached — ``stop`` for a fixed step, whole steps of a variable one —, 0 ok
    / 1 diverged); after each chunk ``ctl`` books it (progress,
    estimate, a checkpoint of ``state(steps done)`` when due) and a stop request ends the run.
    Returns (steps done — for a divergence the step that failed —, status 0 ok, 1 diverged,
    2 stopped)."""
    while done < total:
        m = ctl.next_chunk(done, total)
        w = time.perf_counter()
        reached, code = advance(done, done + m)
        w = time.perf_counter() - w
        if code != 0:
            return reached, 1
        # a chunk may end a little before or after done + m (whole steps of a variable size)
        ctl.chunk_done(reached - done, w, reached, total, lambda d=reached: state(d))
        done = reached
        if ctl.stop_requested and done < total:
            return done, 2
    return done, 0


def check_record_size(rows: int, columns: int, advice: str) -> None:
    """Refuse, before the run, records of ``rows`` × ``columns`` float64 larger than a quarter
    of the physical memory (building the result copies them a few times): InputError with
    ``advice`` (which option thins the records)."""
    need = 8.0 * rows * columns
    try:
        mem = float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return
    if need > 0.25 * mem:
        raise InputError(f"the run would record {rows:,} samples × {columns} values = "
                         f"{need / 1e9:.3g} GB, more than a quarter of the memory "
                         f"({mem / 1e9:.3g} GB): {advice}")


def check_same_run(saved: dict, run_id: dict) -> None:
    """Refuse to resume from a checkpoint of another run: every entry of ``run_id`` (scheme,
    steps, step size, sizes …) must equal the saved one (0-d arrays compared as scalars)."""
    for k, val in run_id.items():
        got = saved.get(k)
        got = got.item() if hasattr(got, "ndim") and got.ndim == 0 else got
        if got != val:
            raise InputError(f"resume: the checkpoint is of another run ({k} = {got!r}, this "
                             f"run has {val!r})")
