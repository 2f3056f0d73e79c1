"""The three action interfaces (paper A.2) executed on a :class:`~navverse.sim.simulator.Simulator`.

* **Discrete** primitives become a single-step waypoint (table ``tab:discrete_actions``): ``forward``
  moves :func:`step_size` meters ahead (0.25 indoor, 1.0 outdoor and indoor-to-outdoor), ``left`` and
  ``right`` are *sidesteps* (strafes) of the same length, ``rotate_*`` turn 30 degrees in place,
  ``small_rotate_*`` 15 degrees; ``stop`` ends the episode. Each runs until the robot has settled on
  the target (within 1 cm and 1 degree, below 3 cm/s), until it is blocked (below), or
  :data:`DISCRETE_TIMEOUT` seconds.
* **Waypoints** in the world frame ``(x, y, yaw)`` are appended to the follower's path and
  executed for a decision period without waiting for the previous ones (streaming). A waypoint equal
  to the last one of the path is not appended again, so an agent may keep sending its current target.
* **Velocity** commands ``(vx, vy, wz)`` in the body frame go straight to the embodiment for a
  decision period, bypassing the follower.

Action names and habitat-lab's names. An action index is a position in :data:`DISCRETE_ACTIONS`
(never renumbered: datasets, agents and submissions use the indices). Habitat-lab's names are accepted
as aliases wherever an action is given by name (:func:`action_index`, :meth:`ActionRunner.discrete`,
``NavVerseEnv.step("move_forward")``):

================  ==================  =====  =====================================================
alias             NavVerse action     index  motion
================  ==================  =====  =====================================================
``move_forward``  ``forward``         1      :func:`step_size` m ahead
``strafe_left``   ``left``            2      sidestep :func:`step_size` m to the left (no turn)
``strafe_right``  ``right``           3      sidestep :func:`step_size` m to the right (no turn)
``turn_left``     ``rotate_left``     4      turn 30 degrees to the left (counter-clockwise)
``turn_right``    ``rotate_right``    5      turn 30 degrees to the right (clockwise)
================  ==================  =====  =====================================================

Note that NavVerse's ``left``/``right`` are sidesteps, not turns: for habitat-lab's turns use
``turn_left``/``turn_right`` (or ``rotate_left``/``rotate_right``).

Blocked primitives. A discrete primitive that makes no progress towards its target for
:data:`BLOCKED_WINDOW` seconds of simulated time is ended early and reported as blocked
(:attr:`ActionRunner.blocked`): a robot facing a wall gives up after about a second instead of pushing
for :data:`DISCRETE_TIMEOUT` (still the hard upper bound). Progress is a drop of the distance error by
more than :data:`BLOCKED_DISTANCE` or of the yaw error by more than :data:`BLOCKED_YAW`, or a turn of
the robot by more than :data:`BLOCKED_YAW` (a differential-drive robot turns towards a sidestep's
target first), since the last progress; a robot close to its target (within 3 cm and 3 degrees) is
settling and never blocked. Progress is measured over the window, not per tick, so a robot
accelerating from rest is not blocked (the longest pause between progress on flat ground is under
0.2 s for both robots), and a primitive that is not blocked runs exactly as it did without the rule.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from navverse.scene_types import scene_profile
from navverse.sim.controller import BRAKING, Waypoint, WaypointFollower, wrap_angle
from navverse.sim.simulator import Simulator
from navverse.sim.world import CONTROL_HZ

__all__ = [
    "ACTION_ALIASES",
    "BLOCKED_DISTANCE",
    "BLOCKED_WINDOW",
    "BLOCKED_YAW",
    "DECISION_PERIOD",
    "DISCRETE_ACTIONS",
    "DISCRETE_TIMEOUT",
    "ActionRunner",
    "action_index",
    "action_name",
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
ACTION_ALIASES: dict[str, str] = {
    "move_forward": "forward",
    "strafe_left": "left",
    "strafe_right": "right",
    "turn_left": "rotate_left",
    "turn_right": "rotate_right",
}
"""Habitat-lab's action names, accepted by name for the NavVerse action of the same motion."""
DISCRETE_TIMEOUT = 8.0
"""Longest a discrete primitive may run (s): the hard upper bound, blocked or not."""
BLOCKED_WINDOW = 1.0
"""Simulated time without progress after which a discrete primitive is blocked (s)."""
BLOCKED_DISTANCE = 0.01
"""Drop of the distance error that counts as progress (m)."""
BLOCKED_YAW = math.radians(1.0)
"""Drop of the yaw error that counts as progress (rad)."""
_CLOSE_DISTANCE = 0.03  # m: within this and _CLOSE_YAW of the target the robot is settling, never blocked
_CLOSE_YAW = math.radians(3.0)
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


def action_name(name: str) -> str:
    """The NavVerse action named ``name`` (a name of :data:`DISCRETE_ACTIONS` or an alias of
    :data:`ACTION_ALIASES`).

    Raises
    ------
    ValueError
        On an unknown name; the message lists the actions and the aliases.
    """
    canonical = ACTION_ALIASES.get(name, name)
    if canonical not in DISCRETE_ACTIONS:
        aliases = ", ".join(f"{a} ({c})" for a, c in ACTION_ALIASES.items())
        raise ValueError(
            f"unknown discrete action {name!r}; choose from: {', '.join(DISCRETE_ACTIONS)} "
            f"or the aliases {aliases}"
        )
    return canonical


def action_index(name: str) -> int:
    """The index in :data:`DISCRETE_ACTIONS` of the action named ``name`` (aliases accepted).

    Raises
    ------
    ValueError
        On an unknown name.
    """
    return DISCRETE_ACTIONS.index(action_name(name))


def discrete_waypoint(action: str, x: float, y: float, yaw: float, *, step: float) -> Waypoint | None:
    """The single-step waypoint of a discrete action from pose ``(x, y, yaw)``; None for ``stop``.

    Raises
    ------
    ValueError
        On an unknown action.
    """
    action = action_name(action)
    if action == "stop":
        return None
    c, s = math.cos(yaw), math.sin(yaw)
    if action == "forward":
        return Waypoint(x + step * c, y + step * s, yaw)
    if action in ("left", "right"):
        side = 1.0 if action == "left" else -1.0
        return Waypoint(x - side * step * s, y + side * step * c, yaw)
    return Waypoint(x, y, wrap_angle(yaw + math.radians(_TURNS[action])))


class _Progress:
    """Whether a primitive still makes progress: the time of the last drop of its distance error by more
    than :data:`BLOCKED_DISTANCE`, of its yaw error by more than :data:`BLOCKED_YAW`, or of a turn of the
    robot by more than :data:`BLOCKED_YAW` (a differential-drive robot turns towards a sidestep's target
    first, away from the target's yaw)."""

    def __init__(self, time: float, error: float, yaw_error: float, yaw: float) -> None:
        self.time, self.error, self.yaw_error, self.yaw = time, error, yaw_error, yaw

    def blocked(self, time: float, error: float, yaw_error: float, yaw: float) -> bool:
        """Note the errors and the heading at ``time``; True when there was no progress for
        :data:`BLOCKED_WINDOW` s and the robot is not close to the target."""
        turned = abs(wrap_angle(yaw - self.yaw)) > BLOCKED_YAW
        if error < self.error - BLOCKED_DISTANCE or yaw_error < self.yaw_error - BLOCKED_YAW or turned:
            self.time, self.error, self.yaw_error, self.yaw = time, error, yaw_error, yaw
            return False
        close = error < _CLOSE_DISTANCE and yaw_error < _CLOSE_YAW
        return not close and time - self.time >= BLOCKED_WINDOW


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
        self.blocked = False
        """Whether the last discrete primitive was ended early, blocked (see the module docstring)."""

    def _pose2d(self) -> tuple[float, float, float]:
        pose = self.sim.pose()
        return float(pose.position[0]), float(pose.position[1]), pose.yaw

    def discrete(self, action: str) -> float:
        """Run a discrete primitive (a name or an alias) until it has settled, is blocked or times out.

        Returns the simulated seconds it took; :attr:`blocked` tells whether it was ended early, blocked.

        Raises
        ------
        ValueError
            On an unknown action.
        """
        self.blocked = False
        x, y, yaw = self._pose2d()
        target = discrete_waypoint(action, x, y, yaw, step=self.step)
        start = self.sim.time
        if target is None:
            self.sim.tick(0.0, 0.0, 0.0)
            return self.sim.time - start
        self.follower.set_path([target], start=(x, y))
        dt = 1.0 / CONTROL_HZ
        progress: _Progress | None = None
        while self.sim.time - start < DISCRETE_TIMEOUT:
            x, y, yaw = self._pose2d()
            error = math.hypot(target.x - x, target.y - y)
            yaw_error = abs(wrap_angle(target.yaw - yaw)) if target.yaw is not None else 0.0
            if error < _SETTLE_DISTANCE and yaw_error < _SETTLE_YAW and self.sim.speed() < _SETTLE_SPEED:
                break
            if progress is None:
                progress = _Progress(self.sim.time, error, yaw_error, yaw)
            elif progress.blocked(self.sim.time, error, yaw_error, yaw):
                self.blocked = True
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
