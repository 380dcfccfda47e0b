"""One driver per sweep store: a lock file ``<store>.lock`` next to the store.

The lock is a small JSON file (pid, host, process start time, start time of the run, command
line) created with ``O_CREAT | O_EXCL``, so of two drivers started at the same moment exactly
one gets it. A second driver is refused with a message naming the running one. A lock left by
a driver that died (kill -9, a crash, a reboot) is *stale* when its host is this host and its
process is gone (or the pid now belongs to a process started at another time): it is taken
over with a warning. A lock from another host cannot be checked and is never taken over: the
message says which file to delete once that driver is known to be gone.
"""

from __future__ import annotations

import contextlib
import json
import os
import socket
import sys
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from geardyn.errors import InputError


class StaleLockWarning(UserWarning):
    """A lock left by a driver that is gone was taken over."""


def lock_path(store: str | Path) -> Path:
    p = Path(store)
    return p.with_name(p.name + ".lock")


def _start_ticks(pid: int) -> str | None:
    """Start time of process ``pid`` in clock ticks since boot (Linux ``/proc``), or None."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return text.rpartition(")")[2].split()[19]


def _alive(info: dict[str, Any]) -> bool:
    """The locking process still runs (same host only; another host: assumed alive)."""
    if info.get("host") != socket.gethostname():
        return True
    pid = int(info.get("pid", -1))
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    ticks = _start_ticks(pid)
    return ticks is None or info.get("start_ticks") in (None, ticks)


def _read(path: Path) -> dict[str, Any] | None:
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        return None
    except (OSError, ValueError):
        return {}


def describe(info: dict[str, Any]) -> str:
    started = info.get("started", "?")
    return (f"pid {info.get('pid', '?')} on host {info.get('host', '?')}, started {started}"
            + (f" ({info['command']})" if info.get("command") else ""))


def _create(path: Path, info: dict[str, Any]) -> bool:
    try:
        fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
    except FileExistsError:
        return False
    except OSError as exc:
        raise InputError(f"--out: cannot create the lock file '{path}': "
                         f"{exc.strerror or exc}") from None
    with os.fdopen(fd, "w") as f:
        json.dump(info, f)
        f.flush()
        os.fsync(f.fileno())
    return True


def _take_over(path: Path, held: dict[str, Any] | dict, pid: int) -> bool:
    """Remove the stale lock ``path`` (whose content was ``held``) atomically: move it aside,
    and put it back if what was moved is another process's fresh lock. True when removed
    (the caller then creates its own); False when it was gone or put back."""
    aside = path.with_name(f"{path.name}.stale-{pid}")
    try:
        os.rename(path, aside)
    except FileNotFoundError:
        return False
    moved = _read(aside)
    if moved is not None and moved != held:  # another process's fresh lock: put it back
        with contextlib.suppress(OSError):
            os.rename(aside, path)
        return False
    with contextlib.suppress(OSError):
        os.unlink(aside)
    return True


@contextlib.contextmanager
def store_lock(store: str | Path) -> Iterator[dict[str, Any]]:
    """Hold the lock of ``store`` for the block; InputError naming the driver holding it."""
    path = lock_path(store)
    pid = os.getpid()
    info = {"pid": pid, "host": socket.gethostname(), "start_ticks": _start_ticks(pid),
            "started": time.strftime("%Y-%m-%d %H:%M:%S %Z"),
            "command": " ".join(sys.argv[:1] + sys.argv[1:])[:300]}
    for _attempt in range(5):
        if _create(path, info):
            break
        held = _read(path)
        if held is None:  # released meanwhile
            continue
        if held and _alive(held):
            raise InputError(
                f"--out: the store '{store}' is in use by another geardyn sweep "
                f"({describe(held)}); wait for it to finish, or if that driver is gone, "
                f"delete '{path}'")
        # stale (or unreadable: a driver killed while writing it): take it over atomically
        if not _take_over(path, held, pid):
            continue
        warnings.warn(f"taking over the lock of '{store}' left by a driver that is gone "
                      f"({describe(held) if held else 'unreadable lock file'})",
                      StaleLockWarning, stacklevel=3)
    else:
        raise InputError(f"--out: could not lock the store '{store}' ('{path}' keeps "
                         "changing): is another geardyn sweep starting on it?")
    try:
        yield info
    finally:
        if _read(path) == info:
            with contextlib.suppress(OSError):
                os.unlink(path)


@contextlib.contextmanager
def wait_lock(path: str | Path, poll_s: float = 0.2) -> Iterator[dict[str, Any]]:
    """Hold the lock file ``<path>.lock`` for the block, waiting while another process holds
    it (a cache entry being computed by another worker); a lock left by a process that is
    gone (same host) is taken over silently — the entry it guarded is written under a
    temporary name and renamed, so nothing half-written is left behind it."""
    lock = Path(str(path) + ".lock")
    pid = os.getpid()
    info = {"pid": pid, "host": socket.gethostname(), "start_ticks": _start_ticks(pid),
            "started": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "nonce": os.urandom(8).hex()}
    unreadable = 0
    while not _create(lock, info):
        held = _read(lock)
        if held is None:
            continue
        if not held and unreadable < 25:  # being written by its creator: wait a moment
            unreadable += 1
            time.sleep(poll_s)
            continue
        if held and _alive(held):
            time.sleep(poll_s)
            continue
        _take_over(lock, held, pid)
    try:
        yield info
    finally:
        if _read(lock) == info:
            with contextlib.suppress(OSError):
                os.unlink(lock)
