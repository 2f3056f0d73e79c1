"""The three action interfaces (paper A.2) executed on a :class:`~navverse.sim.simulator.Simulator`.

* **Discrete** primitives become a single-step waypoint (table ``tab:discrete_actions``): ``forward``,
  ``left``, ``right`` move :func:`step_size` meters (0.25 indoor, 1.0 outdoor and indoor-to-outdoor),
  ``rotate_*`` turn 30 degrees, ``small_rotate_*`` 15 degrees; ``stop`` ends the episode. Each runs
  until the robot has settled on the target (within 1 cm and 1 degree, below 3 cm/s), or
  :data:`DISCRETE_TIMEOUT` seconds.
* **Waypoints** in the world frame ``(x, y, yaw)`` are appended to the follower's path and
  executed for a decision period without waiting for the previous ones (streaming). A waypoint equal
  to the last one of the path is not appended again, so an agent may keep sending its current target.
* **Velocity** commands ``(vx, vy, wz)`` in the body frame go straight to the embodiment for a
  decision period, bypassing the follower.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from navverse.scene_types import scene_profile
from navverse.sim.controller import BRAKING, Waypoint, WaypointFollower, wrap_angle
from navverse.sim.simulator import Simulator
from navverse.sim.world import CONTROL_HZ

__all__ = [
    "DECISION_PERIOD",
    "DISCRETE_ACTIONS",
    "DISCRETE_TIMEOUT",
    "ActionRunner",
    "discrete_waypoint",
    "step_size",
]

DISCRETE_ACTIONS = (
    "stop",
    "forward",
    "left",
    "right",
    "rotate_left",
    "rotate_right",
    "small_rotate_left",
    "small_rotate_right",
)
"""Discrete action names; an action index is a position in this tuple."""
DISCRETE_TIMEOUT = 8.0
"""Longest a discrete primitive may run (s)."""
DECISION_PERIOD = 0.1
"""Simulated time per waypoint or velocity decision (s): the camera's 10 Hz."""
_SETTLE_DISTANCE = 0.01
_SETTLE_YAW = math.radians(1.0)
_SETTLE_SPEED = 0.03
_TURNS = {"rotate_left": 30.0, "rotate_right": -30.0, "small_rotate_left": 15.0, "small_rotate_right": -15.0}


def _same_waypoint(a: Waypoint, b: Waypoint) -> bool:
    """Whether two waypoints are the same target (within 1 mm and 0.01 rad)."""
    if math.hypot(a.x - b.x, a.y - b.y) > 1e-3 or (a.yaw is None) != (b.yaw is None):
        return False
    return a.yaw is None or abs(wrap_angle(a.yaw - b.yaw)) < 1e-2


def step_size(scene_type: str) -> float:
    """Translation of ``forward``/``left``/``right`` (m): the scene type's ``discrete_step_m``
    (:mod:`navverse.scene_types`: 0.25 indoor, 1.0 outdoor and i2o)."""
    return scene_profile(scene_type).discrete_step_m


def discrete_waypoint(action: str, x: float, y: float, yaw: float, *, step: float) -> Waypoint | None:
    """The single-step waypoint of a discrete action from pose ``(x, y, yaw)``; None for ``stop``.

    Raises
    ------
    ValueError
        On an unknown action.
    """
    if action == "stop":
        return None
    c, s = math.cos(yaw), math.sin(yaw)
    if action == "forward":
        return Waypoint(x + step * c, y + step * s, yaw)
    if action in ("left", "right"):
        side = 1.0 if action == "left" else -1.0
        return Waypoint(x - side * step * s, y + side * step * c, yaw)
    if action in _TURNS:
        return Waypoint(x, y, wrap_angle(yaw + math.radians(_TURNS[action])))
    raise ValueError(f"unknown discrete action {action!r}; choose from: {', '.join(DISCRETE_ACTIONS)}")


class ActionRunner:
    """Executes actions on a simulator with the shared waypoint follower.

    Parameters
    ----------
    sim : Simulator
        The robot in its world.
    step : float
        Translation of the discrete actions (m).
    """

    def __init__(self, sim: Simulator, *, step: float) -> None:
        self.sim = sim
        self.step = step
        self.follower = WaypointFollower(limits=sim.robot.max_velocity)

    def _pose2d(self) -> tuple[float, float, float]:
        pose = self.sim.pose()
        return float(pose.position[0]), float(pose.position[1]), pose.yaw

    def discrete(self, action: str) -> float:
        """Run a discrete primitive until it has settled; returns the simulated seconds it took."""
        x, y, yaw = self._pose2d()
        target = discrete_waypoint(action, x, y, yaw, step=self.step)
        start = self.sim.time
        if target is None:
            self.sim.tick(0.0, 0.0, 0.0)
            return self.sim.time - start
        self.follower.set_path([target], start=(x, y))
        dt = 1.0 / CONTROL_HZ
        while self.sim.time - start < DISCRETE_TIMEOUT:
            x, y, yaw = self._pose2d()
            error = math.hypot(target.x - x, target.y - y)
            yaw_error = abs(wrap_angle(target.yaw - yaw)) if target.yaw is not None else 0.0
            if error < _SETTLE_DISTANCE and yaw_error < _SETTLE_YAW and self.sim.speed() < _SETTLE_SPEED:
                break
            # Servo on the target itself, past the 3 cm "reached" radius, until it settles.
            speed = math.sqrt(2.0 * BRAKING * error)
            command = self.follower.track(
                x, y, yaw, target.x, target.y, target.yaw, final=True, dt=dt, speed=speed
            )
            self.sim.tick(*command)
        self.follower.clear()
        self.sim.tick(0.0, 0.0, 0.0)
        return self.sim.time - start

    def waypoints(self, waypoints: Iterable[Waypoint], *, duration: float = DECISION_PERIOD) -> None:
        """Append waypoints to the path being followed and run the follower for ``duration`` s."""
        new = []
        last = self.follower.path[-1] if self.follower.path else None
        for waypoint in waypoints:
            if last is None or not _same_waypoint(waypoint, last):
                new.append(waypoint)
                last = waypoint
        if new:
            if self.follower.done:
                x, y, _ = self._pose2d()
                self.follower.set_path(new, start=(x, y))
            else:
                self.follower.extend(new)
        for _ in range(max(1, round(duration * CONTROL_HZ))):
            self.sim.tick(*self.follower.command(*self._pose2d()))

    def velocity(self, vx: float, vy: float, wz: float, *, duration: float = DECISION_PERIOD) -> None:
        """Hold a body-frame velocity for ``duration`` s (clipped by the embodiment)."""
        self.follower.clear()
        for _ in range(max(1, round(duration * CONTROL_HZ))):
            self.sim.tick(vx, vy, wz)
