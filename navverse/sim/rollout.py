"""Execute a reference path under full physics: the robot tracks its waypoints until it arrives or fails.

:func:`follow_path` hands the whole path to the shared waypoint follower (as an agent streaming
waypoints would), steps the simulator until the follower has reached the last waypoint, the robot
has stopped making progress, or a termination fires, and reports what happened. Episode
verification and the path-following benchmark use it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from navverse.sim.actions import ActionRunner
from navverse.sim.controller import Waypoint
from navverse.sim.simulator import Simulator
from navverse.sim.terminations import TerminationMonitor
from navverse.sim.world import CONTROL_HZ

__all__ = ["PathRollout", "follow_path", "path_waypoints"]

_SAMPLE_EVERY = CONTROL_HZ // 10  # trajectory samples at 10 Hz


@dataclass(frozen=True, eq=False)
class PathRollout:
    """The outcome of following one path.

    Attributes
    ----------
    arrived : bool
        The follower reached the last waypoint (within its 0.03 m tolerance) without a termination.
    termination : str or None
        ``fall``, ``out_of_bounds``, ``stuck`` or ``timeout`` when the rollout ended that way.
    final_distance : float
        Horizontal distance from the robot's final position to the path's end (m).
    duration : float
        Simulated seconds from the start to the end of the rollout.
    traveled : float
        Horizontal length of the executed trajectory (m), summed over 10 Hz samples.
    trajectory : ndarray, shape (K, 8)
        ``[t, x, y, z, qx, qy, qz, qw]`` at 10 Hz and at the end, t from the start.
    collisions : int
        Control ticks with a non-ground contact.
    """

    arrived: bool
    termination: str | None
    final_distance: float
    duration: float
    traveled: float
    trajectory: np.ndarray
    collisions: int


def path_waypoints(points: ArrayLike, *, final_yaw: float | None = None) -> list[Waypoint]:
    """Waypoints along a navmesh path's corners (the first, the start, is dropped)."""
    corners = np.asarray(points, dtype=float).reshape(-1, 3)
    waypoints = [Waypoint(float(p[0]), float(p[1])) for p in corners[1:]]
    if waypoints and final_yaw is not None:
        last = waypoints[-1]
        waypoints[-1] = Waypoint(last.x, last.y, float(final_yaw))
    return waypoints


def follow_path(
    sim: Simulator,
    points: ArrayLike,
    *,
    monitor: TerminationMonitor | None = None,
    final_yaw: float | None = None,
    settle: float = 0.5,
) -> PathRollout:
    """Track a path from where the robot stands, under physics, and report the outcome.

    Parameters
    ----------
    sim : Simulator
        A simulator whose robot is spawned at (or near) the path's start.
    points : array_like, shape (K, 3)
        Path corners, the first being the start (as :meth:`PathFinder.find_path` returns them).
    monitor : TerminationMonitor, optional
        Termination checks (default: fall, out of bounds, stuck after 10 s without progress, and a
        timeout of 300 s).
    final_yaw : float, optional
        Heading to end with; None accepts any.
    settle : float
        Seconds the robot is held still (zero command) before it starts.

    Returns
    -------
    PathRollout
    """
    monitor = monitor if monitor is not None else TerminationMonitor(detect_stuck=True)
    waypoints = path_waypoints(points, final_yaw=final_yaw)
    end = np.asarray(points, dtype=float).reshape(-1, 3)[-1]
    for _ in range(round(settle * CONTROL_HZ)):
        sim.tick(0.0, 0.0, 0.0)
    runner = ActionRunner(sim, step=0.25)
    start_time = sim.time
    monitor.start(sim)
    rows: list[list[float]] = []
    ticks_with_collision = 0

    def sample() -> None:
        pose = sim.pose()
        rows.append([sim.time - start_time, *map(float, pose.position), *map(float, pose.quaternion)])

    sample()
    runner.waypoints(waypoints, duration=1.0 / CONTROL_HZ)
    termination: str | None = None
    ticks = 1
    while True:
        collided = len(sim.collisions)
        if runner.follower.done:
            break
        termination = monitor.check(sim)
        if termination is not None:
            break
        runner.waypoints([], duration=1.0 / CONTROL_HZ)
        ticks += 1
        ticks_with_collision += len(sim.collisions) > collided
        if ticks % _SAMPLE_EVERY == 0:
            sample()
    if rows[-1][0] < sim.time - start_time:
        sample()
    trajectory = np.asarray(rows, dtype=float)
    steps = np.diff(trajectory[:, 1:3], axis=0)
    final = trajectory[-1, 1:3]
    return PathRollout(
        arrived=termination is None,
        termination=termination,
        final_distance=float(math.hypot(*(final - end[:2]))),
        duration=float(trajectory[-1, 0]),
        traveled=float(np.linalg.norm(steps, axis=1).sum()),
        trajectory=trajectory,
        collisions=ticks_with_collision,
    )
