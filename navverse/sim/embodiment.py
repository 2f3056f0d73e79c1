"""The robot interface the controller, environment and evaluator are written against, and its helpers.

An embodiment is a simulated robot in a :class:`~navverse.sim.world.World`: it is spawned at a ground
point, takes body-frame velocity targets (:meth:`Embodiment.set_command`), turns them into forces or
motor targets before every physics step (:meth:`Embodiment.before_step`) and reports its base pose and
velocity. The robots (:mod:`navverse.sim.spot`, :mod:`navverse.sim.turtlebot`) build on the helpers
here; they are created by name through the registry, :mod:`navverse.sim.embodiments`. This module
imports no robot.

Frames: the base frame is x forward, y left, z up; poses are world-frame positions and ``[x, y, z, w]``
quaternions. A robot has fallen when :func:`tilt` of its base exceeds :data:`FALL_TILT`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol, runtime_checkable

import numpy as np

from navverse.sim.camera import optical_from_body

if TYPE_CHECKING:
    from navverse.sim.world import Contact, World

__all__ = [
    "FALL_TILT",
    "Embodiment",
    "RobotBody",
    "camera_mount",
    "clip_command",
    "is_support_contact",
    "tilt",
]

FALL_TILT = math.radians(45.0)
"""A robot whose base z axis is more than this far from world +z has fallen (radians)."""
SUPPORT_MAX_SLOPE = math.radians(45.0)
"""A contact whose normal is steeper than this is a collision, not support."""


@runtime_checkable
class Embodiment(Protocol):
    """A robot simulated in a :class:`~navverse.sim.world.World`.

    Attributes
    ----------
    name : str
        Registry name.
    radius : float
        ``r_robot`` of the metrics and clearance checks (m).
    size : tuple of float
        Length, width and height of the robot's envelope when standing (m).
    max_velocity : tuple of float
        Largest ``|vx|``, ``|vy|`` (m/s) and ``|wz|`` (rad/s) the robot can be commanded.
    camera_to_base : ndarray, shape (4, 4)
        Pose of the camera's optical frame (x right, y down, z forward) in the base frame.
    standing_height : float
        Height of the base origin above level ground when standing (m).
    body : int
        PyBullet body id once spawned (-1 before).
    """

    name: str
    radius: float
    size: tuple[float, float, float]
    max_velocity: tuple[float, float, float]
    camera_to_base: np.ndarray
    standing_height: float
    body: int

    def spawn(self, world: World, position: Sequence[float], yaw: float) -> None:
        """Place the robot standing, at rest, above the ground point `position`, heading `yaw`."""

    def set_command(self, vx: float, vy: float, wz: float) -> None:
        """Set the body-frame velocity target (forward, left, yaw rate), clipped to `max_velocity`."""

    def before_step(self) -> None:
        """Apply forces or motor targets; call before every physics step."""

    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Base position (3,) and quaternion ``[x, y, z, w]`` (4,) in the world frame."""

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Base linear (3,) and angular (3,) velocity in the world frame."""

    def is_ground_contact(self, contact: Contact) -> bool:
        """Whether a contact is normal support (a foot or wheel on navigable terrain), not a collision."""

    def remove(self) -> None:
        """Remove the robot from its world."""


# ---------------------------------------------------------------------------------------------- helpers


class RobotBody:
    """What the built-in robots share: one PyBullet body in one world, a velocity command, removal.

    A subclass calls ``super().__init__()``, sets :attr:`body` and ``_world`` when it spawns and keeps its
    clipped command in ``_command``.

    Attributes
    ----------
    body : int
        PyBullet body id once spawned (-1 before and after :meth:`remove`).
    """

    def __init__(self) -> None:
        self.body = -1
        self._world: World | None = None
        self._command = (0.0, 0.0, 0.0)

    def remove(self) -> None:
        """Remove the robot from its world (it can be spawned again)."""
        if self._world is not None and self.body >= 0 and self._world.client is not None:
            self._world.client.removeBody(self.body)
        self.body = -1
        self._world = None

    @property
    def command(self) -> tuple[float, float, float]:
        """The current (clipped) velocity target."""
        return self._command


def clip_command(
    vx: float, vy: float, wz: float, limits: tuple[float, float, float]
) -> tuple[float, float, float]:
    """Clip a velocity command to ``[-limit, limit]`` per component; NaN is treated as 0.

    Parameters
    ----------
    vx, vy, wz : float
        Forward, left (m/s) and yaw-rate (rad/s) targets.
    limits : tuple of float
        Largest magnitudes of the three components.

    Returns
    -------
    tuple of float
        The clipped command.
    """
    out = []
    for value, limit in zip((vx, vy, wz), limits, strict=True):
        value = float(value)
        out.append(0.0 if math.isnan(value) else min(max(value, -limit), limit))
    return out[0], out[1], out[2]


def tilt(quaternion: Sequence[float]) -> float:
    """Angle (radians) between world +z and the z axis of a body with orientation `quaternion` (xyzw)."""
    x, y, z, w = (float(v) for v in quaternion)
    # The world-z component of the body z axis is 1 - 2 (x^2 + y^2) for a unit quaternion.
    cos_tilt = 1.0 - 2.0 * (x * x + y * y) / (x * x + y * y + z * z + w * w)
    return math.acos(min(1.0, max(-1.0, cos_tilt)))


def camera_mount(position: Sequence[float], *, pitch: float = 0.0) -> np.ndarray:
    """Pose (4x4) of a forward-looking camera's optical frame in the base frame.

    Parameters
    ----------
    position : sequence of float
        Optical centre in the base frame (x forward, y left, z up), in meters.
    pitch : float
        Downward tilt of the optical axis in radians (0: horizontal).

    Returns
    -------
    ndarray, shape (4, 4)
        ``T`` with ``p_base = T[:3, :3] @ p_optical + T[:3, 3]``.
    """
    c, s = math.cos(pitch), math.sin(pitch)
    pitch_down = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # about base +y: x tips down
    pose = np.eye(4)
    pose[:3, :3] = pitch_down @ optical_from_body().T
    pose[:3, 3] = np.asarray(position, dtype=float).reshape(3)
    return pose


def is_support_contact(contact: Contact, support_links: frozenset[int]) -> bool:
    """Whether `contact` is a support link resting on navigable terrain with a normal within 45° of up.

    Parameters
    ----------
    contact : Contact
        A contact from :meth:`~navverse.sim.world.World.contacts`.
    support_links : frozenset of int
        The robot's link indices that touch the ground in normal operation (wheels, casters, feet).
    """
    return (
        contact.link in support_links
        and contact.body.kind == "terrain"
        and contact.body.navigable
        and contact.normal[2] >= math.cos(SUPPORT_MAX_SLOPE)
    )
