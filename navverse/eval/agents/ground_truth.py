"""Privileged reference agents: ``oracle`` follows the episode's reference path, ``gt_goal`` plans one.

Both are the paper's ground-truth settings (Appendix, ``tab:feasibility``): **GT Trajectory**
(:class:`OracleAgent`) calibrates physical executability, since the reference path is the one the
episode was verified with; **GT Goal** (:class:`GTGoalAgent`) knows where the goal instances are and
plans on the navmesh to the closest one, so what it misses is what knowing the goal does not give:
a goal whose nearest navigable point is not within the success distance, a planned path the robot
cannot physically follow.

Both stream the path's corners as waypoints, one per decision, to the shared waypoint follower
(``waypoint`` action mode), render no camera images, and call stop once the base is within
:data:`ARRIVE_DISTANCE` of the path's end.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from navverse.eval.agents.base import AgentTask

__all__ = ["ARRIVE_DISTANCE", "GOAL_SNAP", "GTGoalAgent", "OracleAgent", "PathAgent"]

ARRIVE_DISTANCE = 0.05
"""The agent stops once its base is this close (horizontally, m) to the end of its path."""
GOAL_SNAP = 3.0
"""Half size (m) of the box in which :class:`GTGoalAgent` looks for the navmesh point nearest a goal."""


class PathAgent:
    """Streams a path's corners as waypoints and stops at its end; subclasses choose the path."""

    action_mode = "waypoint"
    privileged = True
    sensors: tuple[str, ...] = ()

    def __init__(self) -> None:
        self._task: AgentTask | None = None
        self._path: np.ndarray | None = None
        self._next = 1

    def reset(self, task: AgentTask) -> None:
        """Start an episode: the path is chosen at the first action."""
        self._task = task
        self._path = None
        self._next = 1

    def plan(self, observation: dict[str, Any], info: dict[str, Any]) -> np.ndarray:
        """The path to follow, ``(K, 3)`` corners from the start; empty when there is none."""
        raise NotImplementedError

    def act(self, observation: dict[str, Any], info: dict[str, Any]) -> np.ndarray:
        """The next corner of the path as ``[x, y, yaw, 0]``, or ``[., ., ., 1]`` (stop) at its end."""
        position = np.asarray(observation["pose"], dtype=float)[:3]
        if self._path is None:
            self._path = np.asarray(self.plan(observation, info), dtype=float).reshape(-1, 3)
            self._next = 1
        path = self._path
        if len(path) < 2:
            return np.array([position[0], position[1], 0.0, 1.0])
        end = path[-1]
        if self._next >= len(path) and math.hypot(*(position[:2] - end[:2])) < ARRIVE_DISTANCE:
            return np.array([end[0], end[1], 0.0, 1.0])
        index = min(self._next, len(path) - 1)
        self._next += 1
        corner, before = path[index], path[index - 1]
        heading = math.atan2(corner[1] - before[1], corner[0] - before[0])
        return np.array([corner[0], corner[1], heading, 0.0])


class OracleAgent(PathAgent):
    """GT Trajectory: follows the episode's reference path (the one its verification rollout took)."""

    def plan(self, observation: dict[str, Any], info: dict[str, Any]) -> np.ndarray:
        """The episode's reference path."""
        return np.asarray(info["reference_path"], dtype=float).reshape(-1, 3)


class GTGoalAgent(PathAgent):
    """GT Goal: plans on the navmesh from where it starts to the closest goal instance.

    Each goal's centre is snapped to the nearest navmesh point within :data:`GOAL_SNAP` m; the path
    goes to the geodesically closest of those. With no reachable goal the agent stops at once.
    """

    def __init__(self) -> None:
        super().__init__()
        self._navmeshes: dict[str, Any] = {}

    def _navmesh(self):
        from navverse.nav.scene_navmesh import load_scene_navmesh

        scene_dir = self._task.scene_dir if self._task is not None else ""
        if not scene_dir:
            raise ValueError("gt_goal needs AgentTask.scene_dir to load the scene's navmesh")
        if scene_dir not in self._navmeshes:
            self._navmeshes[scene_dir] = load_scene_navmesh(scene_dir)
        return self._navmeshes[scene_dir]

    def plan(self, observation: dict[str, Any], info: dict[str, Any]) -> np.ndarray:
        """A navmesh path to the closest goal's nearest navigable point."""
        goals = np.asarray(info["goal_positions"], dtype=float).reshape(-1, 3)
        if not len(goals):
            return np.zeros((0, 3))
        navmesh = self._navmesh()
        snapped = navmesh.snap_point(goals, max_horizontal=GOAL_SNAP, max_vertical=GOAL_SNAP)
        snapped = snapped[np.isfinite(snapped).all(axis=1)]
        if not len(snapped):
            return np.zeros((0, 3))
        start = np.asarray(observation["pose"], dtype=float)[:3]
        return navmesh.find_path_multi(start, snapped).points
