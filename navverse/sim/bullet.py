"""PyBullet, imported and connected without the banners it prints.

PyBullet writes its build time when imported (on standard error) and ``argv[0]=`` when a client
connects (on standard output), from C; a command whose output is data (JSON, tables) must not carry
them. Import ``pybullet`` from here and open clients with :func:`connect`.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from collections.abc import Iterator

__all__ = ["BulletClient", "connect", "pybullet"]


@contextlib.contextmanager
def _quiet(*descriptors: int) -> Iterator[None]:
    """Send what C code writes to the given file descriptors to the null device for the duration."""
    sys.stdout.flush()
    sys.stderr.flush()
    libc = ctypes.CDLL(None)
    saved = [os.dup(fd) for fd in descriptors]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        for fd in descriptors:
            os.dup2(devnull, fd)
        yield
    finally:
        libc.fflush(None)  # C stdio buffers what it printed: drop it while it still goes to the null device
        for fd, copy in zip(descriptors, saved, strict=True):
            os.dup2(copy, fd)
            os.close(copy)
        os.close(devnull)


with _quiet(1, 2):
    import pybullet
    from pybullet_utils.bullet_client import BulletClient


def connect() -> BulletClient:
    """A new physics client in ``DIRECT`` mode (no GUI, no server)."""
    with _quiet(1):
        return BulletClient(connection_mode=pybullet.DIRECT)
