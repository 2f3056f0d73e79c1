"""Why an episode ends (paper A.6, D.2): stop, fall, timeout; and stuck and out of bounds for verification.

* ``fall``: the angle between the robot's z axis and the world's z exceeds
  :data:`~navverse.sim.embodiment.FALL_TILT` (45 degrees);
* ``timeout``: simulated time exceeds :data:`TIMEOUT`;
* ``out_of_bounds``: the robot leaves the scene's bounds (or drops far below them);
* ``stuck``: while commanded to move, it covered less than :data:`STUCK_DISTANCE` in the last
  :data:`STUCK_WINDOW` seconds (used by episode verification, off for agents by default);
* ``agent_timeout`` (:data:`AGENT_TIMEOUT`): the agent itself took too long, in wall-clock time, to
  answer (one ``reset`` or ``act`` call over the step limit, or its calls in an episode over the
  episode limit). ``navverse run-agent`` sets it, not the monitor: the episode ends where the robot
  stands, without a stop, and the run goes on with the next episode.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from navverse.sim.embodiment import FALL_TILT
from navverse.sim.rates import PHYSICS_HZ

if TYPE_CHECKING:
    from navverse.sim.simulator import Simulator

__all__ = ["AGENT_TIMEOUT", "STUCK_DISTANCE", "STUCK_WINDOW", "TIMEOUT", "TerminationMonitor"]

TIMEOUT = 300.0
AGENT_TIMEOUT = "agent_timeout"
"""The termination label of an episode whose agent ran out of wall-clock time (set by the runner)."""
STUCK_WINDOW = 10.0
STUCK_DISTANCE = 0.2


@dataclass
class TerminationMonitor:
    """Checks the termination conditions after every control tick.

    Parameters
    ----------
    timeout : float
        Episode time limit (s of simulated time since :meth:`start`).
    detect_stuck : bool
        Whether ``stuck`` ends the episode.
    """

    timeout: float = TIMEOUT
    detect_stuck: bool = False
    _start: int = 0
    _trail: deque = field(default_factory=deque)

    def start(self, sim: Simulator) -> None:
        """Begin an episode now."""
        self._start = sim.world.steps
        self._trail.clear()

    def elapsed(self, sim: Simulator) -> float:
        """Seconds since :meth:`start`."""
        return (sim.world.steps - self._start) / PHYSICS_HZ

    def check(self, sim: Simulator) -> str | None:
        """The termination label after a tick, or None to go on."""
        pose = sim.pose()
        if pose.tilt > FALL_TILT:
            return "fall"
        if not sim.world.inside_bounds(pose.position):
            return "out_of_bounds"
        if self.detect_stuck:
            now = sim.world.steps
            if not any(abs(v) > 1e-3 for v in sim.command):
                self._trail.clear()  # only time spent commanded to move counts
            self._trail.append((now, float(pose.position[0]), float(pose.position[1])))
            window = round(STUCK_WINDOW * PHYSICS_HZ)
            while now - self._trail[0][0] > window:
                self._trail.popleft()
            then, x, y = self._trail[0]
            if (
                now - then == window
                and math.hypot(pose.position[0] - x, pose.position[1] - y) < STUCK_DISTANCE
            ):
                return "stuck"
        if self.elapsed(sim) > self.timeout:
            return "timeout"
        return None
