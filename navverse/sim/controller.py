"""The shared low-level stack: waypoint path tracking and a PID to body-frame velocity (paper A.3).

At :data:`~navverse.sim.world.CONTROL_HZ` the follower takes the robot's pose, finds the point
:data:`LOOKAHEAD` meters ahead along the remaining waypoint path, and turns the error to it into a
body-frame velocity ``(vx, vy, wz)`` with per-axis PID, clipped to :data:`LIMITS` and the
embodiment's own limits. Intermediate waypoints are passed when the robot's projection on the path
goes beyond them; the last one is *reached* when within :data:`REACH_DISTANCE` and, if it has a
yaw, :data:`REACH_YAW`. Waypoints can be appended while the robot moves (streaming).

Holonomic robots (a legged base with lateral speed) face their direction of travel but may also
side-step; robots without lateral speed (differential drive) turn towards the target first and
drive forward only as much as they face it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from navverse.sim.world import CONTROL_HZ

__all__ = [
    "LIMITS",
    "LOOKAHEAD",
    "PID",
    "REACH_DISTANCE",
    "REACH_YAW",
    "Waypoint",
    "WaypointFollower",
    "wrap_angle",
]

LOOKAHEAD = 0.3
"""Lookahead distance along the path (m)."""
REACH_DISTANCE = 0.03
"""A waypoint is reached within this distance (m)..."""
REACH_YAW = math.radians(3.0)
"""...and, when it has a yaw, within this yaw error (rad)."""
LIMITS = (1.5, 0.3, 1.5)
"""Clip of the commanded ``|vx|`` (m/s), ``|vy|`` (m/s), ``|wz|`` (rad/s)."""
ALIGN_DISTANCE = 0.01
"""A differential drive closer than this to its last waypoint turns to the final yaw (m)."""
REVERSE_DISTANCE = 0.3
"""A differential drive backs up to a last waypoint behind it that is closer than this (m)."""
DRIVE_HEADING = math.radians(20.0)
"""A differential drive turns on the spot, without driving, while its target is this far off its heading."""
_COS_DRIVE = math.cos(DRIVE_HEADING)
BRAKING = 1.0
"""Deceleration planned towards the end of the path (m/s²): speed <= sqrt(2 * BRAKING * remaining)."""


def wrap_angle(angle: float) -> float:
    """``angle`` in (-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))


@dataclass(frozen=True)
class Waypoint:
    """A target pose in the world frame; ``yaw`` None means any heading."""

    x: float
    y: float
    yaw: float | None = None


@dataclass
class PID:
    """A PID on one error signal, with anti-windup: the integral is clamped to ``integral_limit`` and
    only accumulates while ``|error| < integral_zone`` (far from the target the P term saturates the
    command anyway, and an integral gathered there would overshoot it)."""

    kp: float
    ki: float = 0.0
    kd: float = 0.0
    integral_limit: float = 1.0
    integral_zone: float = math.inf
    _integral: float = 0.0
    _previous: float | None = None

    def __call__(self, error: float, dt: float) -> float:
        if abs(error) < self.integral_zone:
            self._integral = min(max(self._integral + error * dt, -self.integral_limit), self.integral_limit)
        derivative = 0.0 if self._previous is None else (error - self._previous) / dt
        self._previous = error
        return self.kp * error + self.ki * self._integral + self.kd * derivative

    def reset(self) -> None:
        """Forget the integral and the previous error."""
        self._integral = 0.0
        self._previous = None


@dataclass
class WaypointFollower:
    """Tracks a waypoint path and outputs body-frame velocity commands.

    Parameters
    ----------
    limits : tuple of float
        The embodiment's own ``(|vx|, |vy|, |wz|)``; the command is clipped to these and :data:`LIMITS`.
    lookahead : float
        Lookahead distance (m).
    """

    limits: tuple[float, float, float] = LIMITS
    lookahead: float = LOOKAHEAD
    path: list[Waypoint] = field(default_factory=list)
    _start: tuple[float, float] | None = None
    _x: PID = field(
        default_factory=lambda: PID(kp=4.0, ki=0.4, kd=0.05, integral_limit=0.2, integral_zone=0.1)
    )
    _y: PID = field(
        default_factory=lambda: PID(kp=4.0, ki=0.4, kd=0.05, integral_limit=0.2, integral_zone=0.1)
    )
    _yaw: PID = field(
        default_factory=lambda: PID(kp=3.0, ki=0.2, kd=0.05, integral_limit=0.3, integral_zone=0.2)
    )
    _turning: bool = False  # a differential drive turning on the spot at the end of its path

    @property
    def clip(self) -> tuple[float, float, float]:
        """The effective velocity limits."""
        return (
            min(LIMITS[0], self.limits[0]),
            min(LIMITS[1], self.limits[1]),
            min(LIMITS[2], self.limits[2]),
        )

    @property
    def holonomic(self) -> bool:
        """Whether the robot can move sideways."""
        return self.clip[1] > 0.0

    # ------------------------------------------------------------------ path

    def set_path(self, waypoints: Iterable[Waypoint], *, start: Sequence[float] | None = None) -> None:
        """Replace the path (``start``: where the robot is, the path's first segment begins there)."""
        self.path = list(waypoints)
        self._start = None if start is None else (float(start[0]), float(start[1]))
        for pid in (self._x, self._y, self._yaw):
            pid.reset()
        self._turning = False

    def extend(self, waypoints: Iterable[Waypoint]) -> None:
        """Append waypoints to the path being followed (streaming)."""
        self.path.extend(waypoints)

    def clear(self) -> None:
        """Drop the path: the follower outputs zero velocity."""
        self.set_path([])

    @property
    def done(self) -> bool:
        """Whether no waypoint is left."""
        return not self.path

    # ------------------------------------------------------------------ control

    def _advance(self, x: float, y: float) -> None:
        """Drop intermediate waypoints the robot has passed (its projection is beyond them)."""
        while len(self.path) > 1:
            a = np.array(self._start if self._start is not None else (x, y))
            b = np.array([self.path[0].x, self.path[0].y])
            seg = b - a
            length2 = float(seg @ seg)
            t = float((np.array([x, y]) - a) @ seg / length2) if length2 > 1e-12 else 1.0
            near = math.hypot(x - b[0], y - b[1]) < max(self.lookahead, REACH_DISTANCE)
            if t < 1.0 and not near:
                return
            self._start = (float(b[0]), float(b[1]))
            self.path.pop(0)

    def remaining(self, x: float, y: float) -> float:
        """Length of the path still to go, from the robot to the last waypoint (m)."""
        if not self.path:
            return 0.0
        total = math.hypot(self.path[0].x - x, self.path[0].y - y)
        for a, b in zip(self.path[:-1], self.path[1:], strict=True):
            total += math.hypot(b.x - a.x, b.y - a.y)
        return total

    def _lookahead_point(self, x: float, y: float) -> tuple[float, float, bool]:
        """The point ``lookahead`` ahead along the path from the robot's projection; and whether it is
        the final waypoint (the remaining path is shorter than the lookahead)."""
        remaining = self.lookahead
        a = np.array(self._start if self._start is not None else (x, y))
        pos = np.array([x, y])
        for i, wp in enumerate(self.path):
            b = np.array([wp.x, wp.y])
            seg = b - a
            length = float(np.linalg.norm(seg))
            if i == 0 and length > 1e-9:  # start from the robot's projection on the first segment
                t = min(max(float((pos - a) @ seg) / (length * length), 0.0), 1.0)
                a = a + t * seg
                seg = b - a
                length = float(np.linalg.norm(seg))
            if length >= remaining and length > 1e-9:
                p = a + seg * (remaining / length)
                return float(p[0]), float(p[1]), False
            remaining -= length
            a = b
        last = self.path[-1]
        return last.x, last.y, True

    def reached(self, x: float, y: float, yaw: float) -> bool:
        """Whether the last waypoint is reached (distance and, if given, yaw)."""
        if not self.path:
            return True
        goal = self.path[-1]
        if len(self.path) > 1 or math.hypot(goal.x - x, goal.y - y) >= REACH_DISTANCE:
            return False
        return goal.yaw is None or abs(wrap_angle(goal.yaw - yaw)) < REACH_YAW

    def command(
        self, x: float, y: float, yaw: float, *, dt: float = 1.0 / CONTROL_HZ
    ) -> tuple[float, float, float]:
        """One control tick: the clipped body-frame velocity towards the path; zeros when done.

        The last waypoint is popped once :meth:`reached` holds; callers that want a settled stop (a
        discrete action) keep commanding the final target themselves.
        """
        if not self.path:
            return 0.0, 0.0, 0.0
        self._advance(x, y)
        if self.reached(x, y, yaw):
            self.path.clear()
            return 0.0, 0.0, 0.0
        tx, ty, final = self._lookahead_point(x, y)
        speed = math.sqrt(2.0 * BRAKING * self.remaining(x, y))
        return self.track(
            x, y, yaw, tx, ty, self.path[-1].yaw if final else None, final=final, dt=dt, speed=speed
        )

    def track(
        self,
        x: float,
        y: float,
        yaw: float,
        tx: float,
        ty: float,
        target_yaw: float | None,
        *,
        final: bool,
        dt: float,
        speed: float = math.inf,
    ) -> tuple[float, float, float]:
        """Body-frame velocity towards the point ``(tx, ty)`` (and ``target_yaw`` when given), at
        most ``speed`` (m/s) along the way."""
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = tx - x, ty - y
        ex, ey = c * dx + s * dy, -s * dx + c * dy  # error in the body frame
        distance = math.hypot(ex, ey)
        vmax_x, vmax_y, wmax = self.clip
        reverse = False
        if final and not self.holonomic:
            # Differential drive: turn towards the target and drive there (backing up to a near target
            # behind), then turn on the spot to the final yaw.
            # Hysteresis: once within ALIGN_DISTANCE it keeps turning until pushed beyond REACH_DISTANCE.
            self._turning = distance < (REACH_DISTANCE if self._turning else ALIGN_DISTANCE)
            if not self._turning:
                heading_error = math.atan2(ey, ex)
                reverse = abs(heading_error) > math.pi / 2 and distance < REVERSE_DISTANCE
                if reverse:
                    heading_error = wrap_angle(heading_error - math.pi)
            else:
                heading_error = 0.0 if target_yaw is None else wrap_angle(target_yaw - yaw)
        elif final and distance < 0.25 and target_yaw is not None:
            heading_error = wrap_angle(target_yaw - yaw)  # close to the end: take the final yaw
        elif distance > 1e-3 and (not final or distance > 0.15):
            heading_error = math.atan2(ey, ex)  # face the direction of travel
        else:
            heading_error = 0.0 if target_yaw is None else wrap_angle(target_yaw - yaw)
        cruise = min(vmax_x, speed)
        vx = self._x(ex, dt) if final else cruise * ex / max(distance, 1e-9)
        vy = self._y(ey, dt) if final else cruise * ey / max(distance, 1e-9)
        wz = self._yaw(heading_error, dt)
        if final and math.hypot(vx, vy) > speed:  # brake towards the end
            vx, vy = vx * speed / math.hypot(vx, vy), vy * speed / math.hypot(vx, vy)
        if not self.holonomic:
            # Differential drive: turn on the spot while the target is more than DRIVE_HEADING off the
            # heading (or, reversing, the back), then drive as it lines up; at the end only turn.
            alignment = (math.cos(heading_error) - _COS_DRIVE) / (1.0 - _COS_DRIVE)
            vx = 0.0 if self._turning else vx * max(0.0, alignment)
            vy = 0.0
        elif abs(heading_error) > math.radians(60) and not final:
            vx *= 0.3  # turn mostly on the spot before a sharp corner
        scale = 1.0
        if abs(vx) > vmax_x:
            scale = min(scale, vmax_x / abs(vx))
        if abs(vy) > vmax_y:
            scale = min(scale, vmax_y / abs(vy)) if self.holonomic else scale
        vx, vy = vx * scale, (vy * scale if self.holonomic else 0.0)
        return float(vx), float(max(-vmax_y, min(vmax_y, vy))), float(max(-wmax, min(wmax, wz)))
