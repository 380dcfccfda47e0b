"""Safe output of long runs: atomic writes, checkpoints, resume, Ctrl-C / SIGTERM (issue 13).

* :func:`write_atomic` writes a file under a temporary name in the target directory and
  renames it (``os.replace``, atomic on POSIX): a killed run never leaves a half-written file
  at the final path.
* :func:`check_output` refuses, before any work, an output into a missing or unwritable
  directory, or onto an existing file (unless overwriting is asked for).
* :func:`save_checkpoint` / :func:`load_checkpoint`: the integrator state (a dict of arrays and
  numbers from :class:`geardyn.solve.control.RunControl`) as an ``.npz`` file, written
  atomically, with a hash of the config and the run options; a resume with another config or
  other options is refused.
* :func:`stop_on_signals`: SIGINT (Ctrl-C) and SIGTERM ask the running loop to stop after its
  current chunk (the compiled loop is never interrupted); a second signal aborts at once.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import signal
import zipfile
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from geardyn.errors import InputError

#: Suffix of the checkpoint file next to the run's output (``run.nc`` → ``run.nc.ckpt.npz``).
CHECKPOINT_SUFFIX = ".ckpt.npz"


def write_atomic(path: str | os.PathLike, write: Callable[[Path], None]) -> None:
    """Call ``write(tmp)`` with a temporary path in ``path``'s directory, then rename it to
    ``path``; the temporary file is removed if writing fails."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()


def save_figure(fig, path: str | os.PathLike, **kwargs) -> None:  # noqa: ANN001 - Figure
    """``fig.savefig`` through :func:`write_atomic` (format from ``path``'s suffix)."""
    fmt = kwargs.pop("format", None) or Path(path).suffix.lstrip(".") or None
    write_atomic(path, lambda tmp: fig.savefig(tmp, format=fmt, **kwargs))


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` (UTF-8) through :func:`write_atomic`."""
    write_atomic(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def check_output(path: str | os.PathLike, option: str, overwrite: bool = False) -> Path:
    """Refuse an output path before the run: missing or unwritable directory, a directory at
    the path, or an existing file unless ``overwrite``."""
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{option}: directory {parent} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{option}: directory {parent} is not writable")
    if path.is_dir():
        raise InputError(f"{option}: {path} is a directory, expected a file name")
    if path.exists() and not overwrite:
        raise InputError(f"{option}: {path} exists; pass --force to overwrite it")
    return path


def checkpoint_path(out: str | os.PathLike) -> Path:
    """The checkpoint file of a run writing ``out``."""
    out = Path(out)
    return out.with_name(out.name + CHECKPOINT_SUFFIX)


def run_hash(cfg, **options: object) -> str:  # noqa: ANN001 - GeardynConfig
    """SHA-256 of the config (its validated JSON form), the run options and the version."""
    import geardyn

    text = json.dumps({"config": json.loads(cfg.model_dump_json()), "options": options,
                       "version": geardyn.__version__}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def save_checkpoint(path: str | os.PathLike, state: dict, digest: str) -> None:
    """Write ``state`` (arrays, numbers, strings) and ``digest`` atomically as ``.npz``."""
    arrays = {k: np.asarray(v) for k, v in state.items()}
    arrays["__run_hash__"] = np.asarray(digest)

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)
            fh.flush()
            os.fsync(fh.fileno())

    write_atomic(path, write)


def load_checkpoint(path: str | os.PathLike, digest: str) -> dict:
    """The state saved by :func:`save_checkpoint`; refused when it belongs to another config
    or other run options (``digest``) or cannot be read."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"--resume: no checkpoint {path} (write one with --checkpoint-every)")
    try:
        with np.load(path, allow_pickle=False) as z:
            state = {k: z[k] for k in z.files}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
        raise InputError(f"--resume: checkpoint {path} is unreadable ({exc}); delete it and "
                         "rerun without --resume") from None
    got = str(state.pop("__run_hash__", ""))
    if got != digest:
        raise InputError(f"--resume: checkpoint {path} belongs to another config or other "
                         "options (seed, run length); rerun without --resume or restore them")
    return {k: (v.item() if v.ndim == 0 else v) for k, v in state.items()}


@contextlib.contextmanager
def stop_on_signals(control) -> Iterator[None]:  # noqa: ANN001 - RunControl
    """SIGINT and SIGTERM call ``control.request_stop`` (the loop ends after its chunk with
    status ``interrupted``); a second signal raises KeyboardInterrupt. Handlers restored on
    exit. Outside the main thread nothing is installed."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    names = {signal.SIGINT: "SIGINT (Ctrl-C)", signal.SIGTERM: "SIGTERM"}

    def handler(signum: int, frame: object) -> None:
        del frame
        if control.stop_requested:
            raise KeyboardInterrupt
        control.request_stop(f"interrupted by {names.get(signum, signum)}")

    old = {s: signal.signal(s, handler) for s in names}
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)
