"""A robot in a world: control ticks, its pose, what it touches, what it stands on, what it sees.

:meth:`Simulator.tick` holds a body-frame velocity command for one control period (1/50 s: four
200 Hz physics steps, the embodiment acting before each). Contacts that are not the robot's normal
support (:meth:`Embodiment.is_ground_contact`) are collisions and are logged with their time in
:attr:`Simulator.collisions`: one entry per contact point per control tick, so pushing against a wall
for a second logs about 50 or more (the submission's ``collisions`` are their distinct times).
:attr:`Simulator.contact_events` counts collision *events* instead: a tick with a collision after a
tick without one.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from navverse.sim.embodiment import Embodiment, tilt
from navverse.sim.world import CONTROL_HZ, PHYSICS_HZ, BodyInfo, World

__all__ = ["Collision", "Pose", "Simulator"]

_SUBSTEPS = PHYSICS_HZ // CONTROL_HZ


@dataclass(frozen=True)
class Pose:
    """The robot base pose: position (3,), quaternion xyzw (4,), and its yaw and tilt (rad)."""

    position: np.ndarray
    quaternion: np.ndarray

    @property
    def yaw(self) -> float:
        """Heading about +z (rad)."""
        x, y, z, w = self.quaternion
        return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))

    @property
    def tilt(self) -> float:
        """Angle between the base's z axis and the world's z axis (rad)."""
        return tilt(self.quaternion)

    def matrix(self) -> np.ndarray:
        """The 4x4 base-to-world transform."""
        x, y, z, w = self.quaternion
        rotation = np.array(
            [
                [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
            ]
        )
        out = np.eye(4)
        out[:3, :3] = rotation
        out[:3, 3] = self.position
        return out


@dataclass(frozen=True)
class Collision:
    """A collision at a time: what was hit (a terrain class or an object) and how hard."""

    time: float
    body: BodyInfo
    force: float


class Simulator:
    """An embodiment acting in a world.

    Parameters
    ----------
    world : World
        The scene in PyBullet.
    embodiment : Embodiment
        The robot (not yet spawned).
    """

    def __init__(self, world: World, embodiment: Embodiment) -> None:
        self.world = world
        self.robot = embodiment
        self.collisions: list[Collision] = []
        self.contact_events = 0
        """Collision events since the robot was spawned: ticks with a collision after one without."""
        self._touching = False
        self.command = (0.0, 0.0, 0.0)
        self.observers: list[Callable[[Simulator], None]] = []  # called after every tick
        self._spawned = False

    @property
    def time(self) -> float:
        """Simulated time since the world was created (s)."""
        return self.world.time

    def spawn(self, position: Sequence[float], yaw: float) -> None:
        """Place the robot standing on the ground at ``position`` facing ``yaw``."""
        if self._spawned:
            self.robot.remove()
        self.robot.spawn(self.world, position, yaw)
        self._spawned = True
        self.collisions = []
        self.contact_events = 0
        self._touching = False
        self.command = (0.0, 0.0, 0.0)

    def tick(self, vx: float, vy: float, wz: float) -> None:
        """Hold the body-frame velocity command for one control period."""
        self.command = (vx, vy, wz)
        self.robot.set_command(vx, vy, wz)
        for _ in range(_SUBSTEPS):
            self.robot.before_step()
            self.world.step()
        logged = len(self.collisions)
        for contact in self.world.contacts(self.robot.body):
            if not self.robot.is_ground_contact(contact):
                self.collisions.append(Collision(self.world.time, contact.body, contact.force))
        touching = len(self.collisions) > logged
        self.contact_events += int(touching and not self._touching)
        self._touching = touching
        for observer in self.observers:
            observer(self)

    def pose(self) -> Pose:
        """The robot's base pose."""
        position, quaternion = self.robot.base_pose()
        return Pose(np.asarray(position, dtype=float), np.asarray(quaternion, dtype=float))

    def speed(self) -> float:
        """Horizontal speed of the base (m/s)."""
        linear, _ = self.robot.base_velocity()
        return float(math.hypot(linear[0], linear[1]))

    def surface(self) -> str | None:
        """Terrain class (or ``"object"``) right under the robot, None over nothing."""
        info, _ = self.world.surface_below(self.pose().position, depth=3.0)
        if info is None:
            return None
        return info.terrain_class if info.kind == "terrain" else "object"

    def camera_to_world(self) -> np.ndarray:
        """The camera's optical frame in the world (4x4)."""
        return self.pose().matrix() @ self.robot.camera_to_base
