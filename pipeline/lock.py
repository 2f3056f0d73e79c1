"""The workspace lock: one build (or clean) at a time works in a build directory.

A build holds an exclusive ``flock`` on ``data/built/build.lock`` from before it plans until it
ends; the operating system releases it when the process ends, however it ends (a ``kill -9``
included), so a lock is never left stale. The holder writes its pid into the file, so a second
build can say whom it waits for. Reading commands (``status``, ``show``, ``eval``) take no lock:
the store is changed only by atomic renames, so they never see a half-written artifact.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import time
from collections.abc import Callable, Iterator
from pathlib import Path

from pipeline.errors import PipelineError

_SETTLE_S = 0.25
"""A lock found taken is tried again for this long before waiting is announced (a ``status``
probe holds it for an instant)."""


class WorkspaceBusyError(PipelineError):
    """Another build holds the workspace lock and the caller would not wait."""


def holder_pid(path: Path) -> int | None:
    """The pid written in the lock file ``path`` (its current or last holder), or None."""
    try:
        text = Path(path).read_text(encoding="ascii").strip()
    except (OSError, ValueError):
        return None
    return int(text) if text.isdigit() else None


def describe_holder(path: Path) -> str:
    """``another build (pid N)``, or ``another build`` when the pid is not known."""
    pid = holder_pid(path)
    return f"another build (pid {pid})" if pid is not None else "another build"


def running_build(path: Path) -> str | None:
    """:func:`describe_holder` if a build holds the lock ``path`` now, else None (takes no lock)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_CLOEXEC)
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return describe_holder(path)
    finally:
        os.close(fd)  # closing releases the shared lock if it was taken
    return None


@contextlib.contextmanager
def workspace_lock(
    path: Path, *, wait: bool = True, on_wait: Callable[[str], None] | None = None
) -> Iterator[None]:
    """Hold the exclusive lock ``path`` for the block.

    Parameters
    ----------
    path : Path
        The lock file (``ArtifactStore.lock_path``); it and its folder are created if needed.
    wait : bool
        Wait for another holder to finish (Ctrl-C stops waiting). False raises instead.
    on_wait : callable, optional
        Called once with :func:`describe_holder` before waiting.

    Raises
    ------
    WorkspaceBusyError
        If ``wait`` is False and another process holds the lock.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
    try:
        _acquire(fd, path, wait=wait, on_wait=on_wait)
        _write_pid(fd)
        yield
    finally:
        os.close(fd)  # releases the lock


def _acquire(fd: int, path: Path, *, wait: bool, on_wait: Callable[[str], None] | None) -> None:
    deadline = time.monotonic() + _SETTLE_S
    while True:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return
        except BlockingIOError:
            if time.monotonic() >= deadline:
                break
            time.sleep(0.05)
    holder = describe_holder(path)
    if not wait:
        raise WorkspaceBusyError(
            f"{holder} holds the workspace {path.parent}; wait for it to end, "
            "or leave out --no-wait to wait for it"
        )
    if on_wait is not None:
        on_wait(holder)
    fcntl.flock(fd, fcntl.LOCK_EX)


def _write_pid(fd: int) -> None:
    """Record this process as the holder (best effort: a full disk must not stop a build here)."""
    with contextlib.suppress(OSError):
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode("ascii"), 0)
