"""A Kobuki-like differential-drive robot, articulated in PyBullet.

Model
-----
One multibody built in code (``createMultiBody``), base plus four links:

- base: a cylinder (diameter :data:`BASE_RADIUS` x 2, :data:`BASE_HEIGHT` tall, its bottom
  :data:`CLEARANCE` above the ground) and a camera mast (a thin cylinder up to :data:`MAST_TOP`),
  :data:`BASE_MASS`; its shell has friction :data:`SHELL_FRICTION` (a smooth bumper);
- two wheels (links 0 left, 1 right) of radius :data:`WHEEL_RADIUS` on revolute joints about the base
  y axis, :data:`TRACK` apart, friction 1.0 (so a wheel's traction is the terrain's friction
  times its normal force), driven by velocity motors (``VELOCITY_CONTROL``) whose torque is limited to
  :data:`WHEEL_TORQUE`;
- two casters (links 2 front, 3 back): frictionless spheres on fixed joints.

:meth:`TurtleBot.set_command` converts ``(vx, wz)`` into the wheel speeds ``(vx -+ wz * TRACK / 2) /
WHEEL_RADIUS`` and sets both motors in one call; ``vy`` is always 0 (the robot cannot move sideways).
:meth:`TurtleBot.before_step` does nothing: the motors hold their targets between commands, and all
motion comes from the wheel contacts, so the robot slips where the wheels' traction (friction times
load) cannot give the acceleration the motors ask for (a 25 degree ramp is climbed at mu = 1 but not at
mu = 0.5), and is stopped by any step higher than its bumper clearance (a 0.2 m curb stops it). The
wheel axle is 1 cm behind the centre of mass, so at rest the robot stands on its wheels (about 93% of
the weight) and front caster. :meth:`TurtleBot.spawn` tilts the robot to the ground's normal, so it also
starts at rest on a ramp.

Limits
------
No wheel suspension (Kobuki's wheels are spring-loaded): on uneven ground the load between wheels and
casters is whatever the rigid contacts give. Motors are ideal velocity servos up to their torque limit
(no back-EMF speed-torque curve, no encoder noise, no acceleration limit of their own).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from navverse.sim.bullet import pybullet
from navverse.sim.embodiment import RobotBody, camera_mount, clip_command, is_support_contact

if TYPE_CHECKING:
    from navverse.sim.world import Contact, World

__all__ = ["AXLE_X", "BASE_RADIUS", "TRACK", "WHEEL_RADIUS", "WHEEL_TORQUE", "TurtleBot"]

BASE_RADIUS = 0.177
"""Radius of the base cylinder (m)."""
BASE_HEIGHT = 0.1
"""Height of the base cylinder (m)."""
CLEARANCE = 0.015
"""Gap between the ground and the base cylinder's bottom (m)."""
MAST_TOP = 0.42
"""Height of the mast's top above the ground (m)."""
MAST_RADIUS = 0.02
MAST_X = -0.05
"""Mast axis, x in the base frame (m)."""
BASE_MASS = 4.0
"""Mass of base, mast and payload (kg)."""
WHEEL_RADIUS = 0.035
"""Wheel radius (m). The wheels' collision shapes are spheres: on the ground a sphere on an axle rolls
like a disc, and it collides with one analytic contact where a cylinder gets up to four from GJK (the
robot's physics costs about half as much)."""
WHEEL_MASS = 0.15
TRACK = 0.23
"""Distance between the wheels' centre planes (m)."""
WHEEL_TORQUE = 1.0
"""Largest torque of one wheel motor (N m)."""
CASTER_RADIUS = 0.015
CASTER_X = 0.12
"""Casters at x = +-CASTER_X in the base frame (m)."""
CASTER_MASS = 0.02
AXLE_X = -0.01
"""Wheel axle, x in the base frame (m): 1 cm behind the centre of mass, so the robot rests on its wheels
and front caster instead of balancing on the wheels."""
SHELL_FRICTION = 0.3
"""Friction of the base and mast (multiplied by the other body's)."""
CAMERA_HEIGHT = 0.4
"""Height of the camera above the ground (m)."""

_BASE_Z = CLEARANCE + BASE_HEIGHT / 2.0  # base origin (cylinder centre) above the ground
_LEFT, _RIGHT, _FRONT, _BACK = 0, 1, 2, 3


class TurtleBot(RobotBody):
    """A Kobuki-like differential-drive robot (see the module docstring).

    The robot is created unspawned; :meth:`spawn` builds it in a world.
    """

    name = "turtlebot"
    radius = 0.2
    size = (2.0 * BASE_RADIUS, 2.0 * BASE_RADIUS, MAST_TOP)
    max_velocity = (0.7, 0.0, 2.8)
    standing_height = _BASE_Z
    """Height of the base origin (mid-axle, at the base cylinder's centre height) above flat ground (m)."""
    wheel_joints = (_LEFT, _RIGHT)
    """Joint indices of the left and right wheels."""

    def __init__(self) -> None:
        super().__init__()
        self.camera_to_base = camera_mount(
            (MAST_X + MAST_RADIUS - AXLE_X, 0.0, CAMERA_HEIGHT - self.standing_height)
        )
        self._support = frozenset((_LEFT, _RIGHT, _FRONT, _BACK))

    # ------------------------------------------------------------------ lifecycle

    def spawn(self, world: World, position: Sequence[float], yaw: float) -> None:
        """Build the robot at rest on the ground point `position`, heading `yaw`; the command is reset to 0.

        The robot stands on its wheels and casters, tilted to the ground's normal below `position`.
        """
        if self.body >= 0:
            raise RuntimeError("this TurtleBot is already spawned; remove() it first")
        c = world.client
        mast_length = MAST_TOP - CLEARANCE - BASE_HEIGHT
        base = c.createCollisionShapeArray(
            [pybullet.GEOM_CYLINDER, pybullet.GEOM_CYLINDER],
            radii=[BASE_RADIUS, MAST_RADIUS],
            lengths=[BASE_HEIGHT, mast_length],
            collisionFramePositions=[[0.0, 0.0, 0.0], [MAST_X, 0.0, (BASE_HEIGHT + mast_length) / 2.0]],
        )
        wheel = c.createCollisionShape(pybullet.GEOM_SPHERE, radius=WHEEL_RADIUS)
        caster = c.createCollisionShape(pybullet.GEOM_SPHERE, radius=CASTER_RADIUS)
        wheel_z = WHEEL_RADIUS - _BASE_Z
        caster_z = CASTER_RADIUS - _BASE_Z
        base_position, base_orientation = self._stance(world, position, yaw)
        self.body = c.createMultiBody(
            baseMass=BASE_MASS,
            baseCollisionShapeIndex=base,
            basePosition=base_position,
            baseOrientation=base_orientation,
            linkMasses=[WHEEL_MASS, WHEEL_MASS, CASTER_MASS, CASTER_MASS],
            linkCollisionShapeIndices=[wheel, wheel, caster, caster],
            linkVisualShapeIndices=[-1] * 4,
            linkPositions=[
                (AXLE_X, TRACK / 2.0, wheel_z),
                (AXLE_X, -TRACK / 2.0, wheel_z),
                (CASTER_X, 0.0, caster_z),
                (-CASTER_X, 0.0, caster_z),
            ],
            linkOrientations=[(0.0, 0.0, 0.0, 1.0)] * 4,
            linkInertialFramePositions=[(0.0, 0.0, 0.0)] * 4,
            linkInertialFrameOrientations=[(0.0, 0.0, 0.0, 1.0)] * 4,
            linkParentIndices=[0] * 4,
            linkJointTypes=[
                pybullet.JOINT_REVOLUTE,
                pybullet.JOINT_REVOLUTE,
                pybullet.JOINT_FIXED,
                pybullet.JOINT_FIXED,
            ],
            linkJointAxis=[(0.0, 1.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, 1.0)],
        )
        # Only touching contacts go to the solver: a rolling wheel's manifold keeps up to four points,
        # most of them already lifted off the ground, and solving those doubled the cost of a step.
        frictions = {-1: SHELL_FRICTION, _LEFT: 1.0, _RIGHT: 1.0, _FRONT: 0.0, _BACK: 0.0}
        for link, friction in frictions.items():
            c.changeDynamics(
                self.body,
                link,
                lateralFriction=friction,
                rollingFriction=0.0,
                spinningFriction=0.0,
                restitution=0.0,
                contactProcessingThreshold=0.0,
            )
        self._world = world
        self._state = c.getBasePositionAndOrientation
        self._velocity = c.getBaseVelocity
        self._motors = c.setJointMotorControlArray
        self._command = (0.0, 0.0, 0.0)
        self._apply_command()

    def _stance(
        self, world: World, position: Sequence[float], yaw: float
    ) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """Base pose resting on the ground at `position`: tilted to the surface's normal on a slope."""
        x, y, z = (float(v) for v in position)
        hit = world.client.rayTest((x, y, z + 0.3), (x, y, z - 0.5))[0]
        nx, ny, nz = hit[4] if hit[0] >= 0 else (0.0, 0.0, 1.0)
        ground = hit[3][2] if hit[0] >= 0 else z
        if nz < math.cos(math.radians(45.0)):  # a wall, not ground: stand level
            nx, ny, nz = 0.0, 0.0, 1.0
        # The shortest rotation taking +z to the normal, after the yaw.
        angle = math.acos(min(1.0, nz))
        sideways = math.hypot(nx, ny)
        ax, ay = (-ny / sideways, nx / sideways) if sideways > 1e-9 else (0.0, 0.0)
        s = math.sin(angle / 2.0)
        tilt_q = (ax * s, ay * s, 0.0, math.cos(angle / 2.0))
        _, orientation = world.client.multiplyTransforms(
            (0.0, 0.0, 0.0), tilt_q, (0.0, 0.0, 0.0), (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))
        )
        up = self.standing_height
        rotation = np.array(world.client.getMatrixFromQuaternion(orientation)).reshape(3, 3)
        center = np.array((x + nx * up, y + ny * up, ground + nz * up)) - rotation[:, 0] * AXLE_X
        return tuple(center.tolist()), tuple(orientation)  # type: ignore[return-value]

    # ------------------------------------------------------------------ control

    def set_command(self, vx: float, vy: float, wz: float) -> None:
        """Set the velocity target, clipped to :attr:`max_velocity` (so ``vy`` becomes 0).

        The wheel motors get their new speeds at once, and only when the command changes.
        """
        command = clip_command(vx, vy, wz, self.max_velocity)
        if command != self._command:
            self._command = command
            if self.body >= 0:
                self._apply_command()

    def wheel_speeds(self) -> tuple[float, float]:
        """Target angular speeds (rad/s) of the left and right wheels for the current command."""
        vx, _, wz = self._command
        half = wz * TRACK / 2.0
        return (vx - half) / WHEEL_RADIUS, (vx + half) / WHEEL_RADIUS

    def _apply_command(self) -> None:
        self._motors(
            self.body,
            [_LEFT, _RIGHT],
            pybullet.VELOCITY_CONTROL,
            targetVelocities=list(self.wheel_speeds()),
            forces=[WHEEL_TORQUE, WHEEL_TORQUE],
        )

    def before_step(self) -> None:
        """Nothing to do: the wheel motors hold the targets :meth:`set_command` gave them."""

    # ------------------------------------------------------------------ state

    def _axle_offset(self, orientation: Sequence[float]) -> np.ndarray:
        """World vector from the base cylinder's centre to the base origin (mid-axle), (3,)."""
        x, y, z, w = orientation
        return AXLE_X * np.array([1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + z * w), 2.0 * (x * z - y * w)])

    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Base origin (3,) and orientation ``[x, y, z, w]`` (4,) in the world frame.

        The origin is the midpoint of the wheel axle at the base cylinder's centre height: the point a
        differential drive turns about, as ROS robots put ``base_link``.
        """
        position, orientation = self._state(self.body)
        return np.array(position) + self._axle_offset(orientation), np.array(orientation)

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Linear (3,) velocity of the base origin and angular (3,) velocity, in the world frame."""
        linear, angular = self._velocity(self.body)
        _, orientation = self._state(self.body)
        angular = np.array(angular)
        return np.array(linear) + np.cross(angular, self._axle_offset(orientation)), angular

    def is_ground_contact(self, contact: Contact) -> bool:
        """True for a wheel or caster on navigable terrain (normal within 45° of up); else a collision."""
        return is_support_contact(contact, self._support)
