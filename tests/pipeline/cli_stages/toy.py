"""A slow deterministic writer (optionally with a child process, or killed midway) and a stage that meets
a full disk."""

from __future__ import annotations

import logging
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Annotated

import numpy as np
from pydantic import Field

from pipeline import Params, StageContext, stage


class SlowParams(Params):
    parts: Annotated[int, Field(ge=1)] = 5
    delay_s: Annotated[float, Field(ge=0)] = 0.1
    child: bool = False
    die_at: Annotated[int, Field(ge=0)] = 0
    gate: str = ""
    """A path (relative to the workspace): after the first part, wait until it exists."""


@stage(name="toy_slow", outputs=["numbers"])
def toy_slow(ctx: StageContext, params: SlowParams) -> None:
    """Numbers written one part at a time (``part_*.npy``, ``numbers.npy``), logging each part."""
    helper = None
    if params.child:  # a process of the stage's own, which must end with the stage
        helper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    values = ctx.rng.random(params.parts)
    for index, value in enumerate(values):
        ctx.log.info("part %d of %d", index + 1, params.parts)
        if index + 1 == params.die_at:  # as the out-of-memory killer would
            os.kill(os.getpid(), signal.SIGKILL)
        np.save(ctx.output / f"part_{index:03d}.npy", np.array([value]))
        if index == 0 and params.gate:
            ctx.log.info("waiting for %s", params.gate)
            while not Path(params.gate).exists():
                time.sleep(0.02)
        ctx.progress(index + 1, params.parts, "parts")
        time.sleep(params.delay_s)
    np.save(ctx.output / "numbers.npy", values)
    if helper is not None:
        helper.kill()
        helper.wait()


class FullDiskParams(Params):
    pass


@stage(name="toy_full_disk", outputs=["numbers"])
def toy_full_disk(ctx: StageContext, params: FullDiskParams) -> None:
    """Logs to a full device and writes to it (``/dev/full``: every write fails with ENOSPC)."""
    ctx.log.addHandler(logging.FileHandler("/dev/full"))
    for index in range(50):
        ctx.log.info("line %d", index)
    with open("/dev/full", "wb") as handle:
        handle.write(b"x" * 4096)
