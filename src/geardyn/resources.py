"""Resource estimates made before any allocation (issue 20).

A run, a sensor channel, a Campbell table or a sweep store is sized from its inputs before it
starts; an input that would need more than the limits below is refused with an
:class:`~geardyn.errors.InputError` naming the field or option and the estimate, instead of
allocating tens of GB or running for days. These are limits on work and memory, not physics:

- :data:`MAX_STEPS`: time steps of one integration (1e9: at ~1 µs per step for the smallest
  model, over 15 min; more is almost always a time step typed in the wrong unit);
- :func:`max_bytes`: the largest single record (a channel, a result's time history, a sweep
  variable), default 4 GiB; the environment variable ``GEARDYN_MAX_MEMORY_GB`` raises it.

:func:`run_problems` lists the problems of a config's run (its own run length or the
overrides of the command line or a sweep spec); the config loader, ``geardyn simulate``,
``geardyn transmission``, ``geardyn diagnose`` and ``geardyn sweep --check`` call it.
"""

from __future__ import annotations

import math
import os
from typing import Any

from geardyn.errors import InputError

#: Most time steps of one integration (module docstring).
MAX_STEPS = 1e9
#: Default of :func:`max_bytes` (bytes).
DEFAULT_MAX_BYTES = 4 * 2**30
#: Bytes per stored number (float64).
ITEM = 8


def max_bytes() -> float:
    """Largest single record (bytes): ``GEARDYN_MAX_MEMORY_GB`` (GiB) or 4 GiB."""
    text = os.environ.get("GEARDYN_MAX_MEMORY_GB", "")
    try:
        value = float(text) * 2**30 if text else DEFAULT_MAX_BYTES
    except ValueError:
        value = DEFAULT_MAX_BYTES
    return value if math.isfinite(value) and value > 0 else DEFAULT_MAX_BYTES


def _gb(n: float) -> str:
    return f"{n / 2**30:.3g} GiB"


def steps_problem(where: str, duration_s: float, step_s: float, what: str = "") -> str | None:
    """A message when ``duration_s / step_s`` exceeds :data:`MAX_STEPS`, else None."""
    if not (duration_s > 0 and step_s > 0):
        return None
    steps = duration_s / step_s
    if steps <= MAX_STEPS:
        return None
    return (f"{where}: {step_s:g} s steps over {what or f'{duration_s:g} s'} are {steps:.3g} "
            f"time steps, above the limit of {MAX_STEPS:.0e} (a time step in the wrong unit?)")


def bytes_problem(where: str, values: float, what: str) -> str | None:
    """A message when ``values`` float64 numbers exceed :func:`max_bytes`, else None."""
    need = values * ITEM
    if not math.isfinite(need) or need > max_bytes():
        return (f"{where}: {what} would hold {values:.3g} values ({_gb(need)}), above the "
                f"limit of {_gb(max_bytes())} per record (set GEARDYN_MAX_MEMORY_GB to raise it)")
    return None


def check(problem: str | None) -> None:
    """Raise an InputError for a problem message."""
    if problem:
        raise InputError(problem)


def _sensor_problems(cfg: Any, duration_s: float, length: str) -> list[str]:
    out = []
    for i, s in enumerate(getattr(cfg, "sensors", None) or []):
        rate = getattr(s, "sample_rate_hz", None)
        if rate:
            p = bytes_problem(f"sensors[{i}] '{s.name}'.sample_rate_hz", rate * duration_s,
                              f"{rate:g} Hz over {length}: the channel's samples")
            if p:
                out.append(p)
    return out


def run_problems(cfg: Any, kind: str | None = None, t_end_s: float | None = None,
                 revolutions: float | None = None, *, t_end_name: str | None = None,
                 revolutions_name: str | None = None) -> list[str]:
    """Problems of the run of ``cfg``'s model ``kind`` (default: every model it describes):
    time steps, stored samples of the result and of every sensor channel. ``t_end_s`` /
    ``revolutions`` override the config's run length; ``*_name`` name them in the messages
    (an option such as ``--t-end``)."""
    out: list[str] = []
    lumped = (("planetary", "planetary_dynamics"), ("mechanism", "dynamics"))
    for model, section in lumped:
        spec = getattr(cfg, section, None)
        sim = getattr(spec, "simulation", None) if spec is not None else None
        if sim is None or kind not in (None, model):
            continue
        t = sim.t_end_s if t_end_s is None else t_end_s
        where_t = t_end_name or f"{section}.simulation.t_end_s"
        length = f"{where_t} = {t:g} s"
        p = steps_problem(f"{section}.simulation.dt_s", t, sim.dt_s, length)
        if p:
            out.append(p)
        out.extend(_sensor_problems(cfg, t, length))
    tr = getattr(cfg, "transmission", None)
    if tr is not None and kind in (None, "transmission") and tr.speed_law is not None:
        law, sim = tr.speed_law, tr.simulation
        revs = revolutions or (sim.revolutions if sim is not None and sim.revolutions
                               else law.revolutions)
        where = revolutions_name or "transmission.speed_law.revolutions"
        duration = revs * 60.0 / min(law.start_rpm, law.end_rpm)  # upper bound of the ramp
        length = f"{where} = {revs:g} (≤ {duration:.3g} s)"
        rate = sim.record_rate_hz if sim is not None else 50_000.0
        p = bytes_problem(where, rate * duration, f"{rate:g} Hz records over {length}")
        if p:
            out.append(p)
        step = sim.time_step_s if sim is not None else None
        if step:
            p = steps_problem(where, duration, step, length)
            if p:
                out.append(p)
        out.extend(_sensor_problems(cfg, duration, length))
    return out


def check_run(cfg: Any, kind: str | None = None, t_end_s: float | None = None,
              revolutions: float | None = None, **names: str) -> None:
    """:func:`run_problems` as an InputError (one line per problem)."""
    problems = run_problems(cfg, kind, t_end_s, revolutions, **names)
    if problems:
        raise InputError("\n".join(problems))
