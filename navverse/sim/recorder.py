"""Record a rollout in the submission format (DESIGN.md §3): timed base poses, stop, collisions.

A :class:`RolloutRecorder` attached to a :class:`~navverse.sim.simulator.Simulator` samples the base
pose at :data:`RECORD_HZ` (the camera's rate) and at the end, so a trajectory row is
``[t, x, y, z, qx, qy, qz, qw]`` with ``t`` in seconds since the episode began. A PlaceNav episode's
record also names the ``instruction_type`` its agent was given.
"""

from __future__ import annotations

import gzip
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from navverse.files import atomic_write
from navverse.sim.rates import CONTROL_HZ

if TYPE_CHECKING:
    from navverse.sim.simulator import Simulator

__all__ = ["RECORD_HZ", "RolloutRecorder", "write_submission"]

RECORD_HZ = 10
_EVERY = CONTROL_HZ // RECORD_HZ


@dataclass
class RolloutRecorder:
    """Collects one episode's trajectory; :meth:`finish` returns its submission record.

    ``instruction_type`` (PlaceNav episodes only; None for the other tasks) is written into the record.
    """

    episode_id: str
    rows: list[list[float]] = field(default_factory=list)
    instruction_type: str | None = None
    _start: float = 0.0
    _ticks: int = 0
    _first_collision: int = 0
    _sim: Simulator | None = None

    def attach(self, sim: Simulator) -> None:
        """Start recording on ``sim`` now (records the current pose as t = 0)."""
        self._sim = sim
        self._start = sim.time
        self._ticks = 0
        self._first_collision = len(sim.collisions)
        self.rows = []
        self._record(sim)
        sim.observers.append(self._on_tick)

    def _record(self, sim: Simulator) -> None:
        pose = sim.pose()
        self.rows.append(
            [round(sim.time - self._start, 6), *map(float, pose.position), *map(float, pose.quaternion)]
        )

    def _on_tick(self, sim: Simulator) -> None:
        self._ticks += 1
        if self._ticks % _EVERY == 0:
            self._record(sim)

    def finish(self, *, stop: bool, termination: str | None) -> dict[str, Any]:
        """Stop recording; the submission record of the episode."""
        sim = self._sim
        if sim is None:
            raise RuntimeError("the recorder was never attached")
        if self.rows[-1][0] < sim.time - self._start - 1e-9:
            self._record(sim)
        if self._on_tick in sim.observers:
            sim.observers.remove(self._on_tick)
        collisions = sorted({round(c.time - self._start, 3) for c in sim.collisions[self._first_collision :]})
        record = {
            "episode_id": self.episode_id,
            "trajectory": self.rows,
            "stop": bool(stop),
            "collisions": collisions,
            "termination": termination,
        }
        if self.instruction_type is not None:
            record["instruction_type"] = self.instruction_type
        return record


def write_submission(records: list[dict[str, Any]], path: str | Path) -> Path:
    """Write records as JSONL (gzipped when the name ends in ``.gz``), one episode per line, atomically
    (a temporary file beside it, then renamed over it)."""
    path = Path(path)
    text = "".join(json.dumps(r, separators=(",", ":")) + "\n" for r in records).encode()
    data = gzip.compress(text, mtime=0) if path.suffix == ".gz" else text
    with atomic_write(path) as handle:
        handle.write(data)
    return path
