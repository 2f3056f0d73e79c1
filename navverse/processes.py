"""Helper processes that end with the process that started them.

A pool worker that outlives its parent (the parent was killed with SIGKILL, or died of memory) goes
on using a core and memory for nothing. :func:`end_with_parent` is the initializer of every process
pool of the toolkit, so that no kill of a build, a verification or an agent run leaves workers
behind.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time

__all__ = ["end_with_parent"]

_PR_SET_PDEATHSIG = 1
"""``prctl`` option: the signal the kernel sends this process when its parent ends (Linux)."""


def end_with_parent() -> None:
    """End this process when its parent ends: at once on Linux (``PR_SET_PDEATHSIG``), else within 0.5 s.

    Also ignores SIGINT: a terminal's Ctrl-C reaches the whole process group, and the parent decides
    how its helpers end (no traceback from each of them).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    parent = os.getppid()
    if sys.platform.startswith("linux"):
        try:
            armed = ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0
        except (OSError, AttributeError):
            armed = False
        if armed:
            if os.getppid() != parent:  # the parent ended before the signal was armed
                os._exit(1)
            return
    threading.Thread(target=_watch, args=(parent,), name="parent-watch", daemon=True).start()


def _watch(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(0.5)
    os._exit(1)
