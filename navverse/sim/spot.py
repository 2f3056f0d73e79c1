"""A Spot-sized legged robot as a reduced-order model: a rigid trunk on four ray-cast spring legs.

Model
-----
The trunk is one rigid box (:data:`BODY_SIZE`, :data:`MASS`, the box's inertia) with a second box under
it between the hips (:data:`LEG_ZONE`) that stands for the legs in collisions: walls, furniture and
steps higher than :data:`MAX_STEP` stop the robot there. Each of the four legs is a ray cast down the
trunk's -z axis from a hip at the trunk's bottom corners (:data:`HIPS`), every physics step, in one
``rayTestBatch``, up to :data:`LEG_REACH`. A leg whose ray meets a static body is a spring-damper along
the trunk's z axis::

    N = clip(k * (L_i - d) - c * d_dot, 0, LEG_MAX_FORCE)

with ``d`` the hip-to-ground distance, ``d_dot`` the hip's velocity along the leg and ``L_i`` the leg's
rest length, which the stance sets so the trunk stays level over uneven ground (as a legged robot's
locomotion controller does): ``L_i = LEG_REST + mean(g) - g_i``, clipped to [:data:`LEG_MIN`,
:data:`LEG_REACH`], ``g_i`` the height of the ground under leg ``i`` and ``mean(g)`` over the legs that
found ground. The same foot also pushes tangentially to the ground (the plane of the hit normal ``n``):
towards the rigid-body velocity the command asks for at that foot (``v + w x r``, so one law gives
forward, lateral and yaw motion), plus a feed-forward ``h`` that makes the foot's reaction vertical
when the velocity is right, so the legs hold the robot on a slope::

    f_t = (MASS / 4) * TRACTION_GAIN * (v_target(foot) - v(hip)) + h,
    |f_t| <= min(mu * N_n, TRACTION_MAX)

where ``mu`` is the friction of the body the ray hit (its terrain class's; 0.6 for objects) and
``N_n`` the leg force along the ground normal. All leg forces act at the foot points (the ray hits)
and are summed into one force and one torque per step. Nothing else holds the trunk up or level, so:

- a curb or step up to :data:`MAX_STEP` (0.32 m) is climbed: the legs over it find the higher ground,
  shorten, and the trunk rises level; a higher one meets the leg box and stops the robot;
- stepping down, the legs over the lower level extend (up to :data:`LEG_REACH`) and take the load;
- a ledge or hole deeper than a leg reaches leaves legs with nothing under them: the trunk pitches or
  rolls over the supporting legs and falls (a tilt beyond :data:`~navverse.sim.embodiment.FALL_TILT`);
- traction is friction-limited per foot, so low-friction ground slows acceleration, braking and turning,
  and a slope steeper than the friction allows cannot be climbed or stood on (the robot slides down);
- walls and furniture stop the trunk or the leg box (contacts of the base, reported by ``World.contacts``).

Parameters (module constants): trunk 1.1 x 0.5 x 0.2 m, 32 kg; hips at (+-0.35, +-0.2) m at the trunk's
bottom; rest leg length 0.48 m on level ground (0.15-0.72 m), standing compression 0.03 m (k = 2616 N/m
per leg, c = 290 N s/m, about critical for heave); leg force <= 4x its standing load; traction gain
8 /s (time constant 0.125 s); traction of one foot <= its standing load (so <= 1 g for the robot);
trunk friction 0.5; leg box 0.8 x 0.5 m, from the trunk down to 0.32 m above the ground. Standing on
flat ground the trunk's centre is 0.55 m and the camera 0.6 m above the ground.

Limits
------
No gait, no swing legs: feet are always under the hips, so footholds are not chosen, a foot can find
support on a surface a real foot could not reach (e.g. the top of a thin rail), and a step is climbed
without lifting a leg. The legs stay perpendicular to the trunk, so on slopes beyond ~25 degrees the
uphill legs unload and the robot slides or tips back (a real Spot manages about 30). Obstacles lower
than :data:`MAX_STEP` are walked over as if stepped on. :meth:`Spot.is_ground_contact` is always False
because every PyBullet contact of this robot is the trunk or the leg box touching something (the legs'
support is given by :meth:`Spot.leg_forces`). Velocity is tracked without position hold: a zero command
stops the robot but small pushes (or a slope's residual) move it a few centimetres.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from navverse.sim._legs import LegModel
from navverse.sim.bullet import pybullet
from navverse.sim.embodiment import RobotBody, camera_mount, clip_command
from navverse.sim.world import GRAVITY, OBJECT_FRICTION

if TYPE_CHECKING:
    from navverse.sim.world import Contact, World

__all__ = ["BODY_SIZE", "HIPS", "LEG_MIN", "LEG_REACH", "LEG_REST", "LEG_ZONE", "MASS", "MAX_STEP", "Spot"]

MASS = 32.0
"""Mass of the robot (kg)."""
BODY_SIZE = (1.1, 0.5, 0.2)
"""Trunk box: length, width, height (m)."""
HIPS = ((0.35, 0.2), (0.35, -0.2), (-0.35, 0.2), (-0.35, -0.2))
"""Hip positions (x, y) in the base frame, at the trunk's bottom face (front left, FR, RL, RR)."""
LEG_REST = 0.48
"""Unloaded leg length from hip to foot on level ground (m)."""
LEG_MIN = 0.15
"""Shortest rest length of a leg (m): a fully folded leg."""
LEG_REACH = 0.72
"""Longest reach of a leg from the hip (m): ground farther below a hip gives that leg no support."""
STANDING_COMPRESSION = 0.03
"""Leg compression under the robot's own weight (m)."""
LEG_STIFFNESS = MASS * GRAVITY / 4.0 / STANDING_COMPRESSION
"""Spring constant per leg (N/m)."""
LEG_DAMPING = 290.0
"""Damping per leg (N s/m); near critical for heave."""
LEG_MAX_FORCE = 4.0 * MASS * GRAVITY / 4.0
"""Largest push of one leg (N)."""
TRACTION_GAIN = 8.0
"""Velocity-error gain of the foot traction (1/s)."""
TRACTION_MAX = GRAVITY * MASS / 4.0
"""Largest tangential force of one foot regardless of friction (N): the actuators' limit, its standing
load."""
MAX_STEP = 0.32
"""Highest step (curb, obstacle) the legs climb (m)."""
LEG_ZONE = (0.8, 0.5, LEG_REST - STANDING_COMPRESSION - MAX_STEP)
"""Box under the trunk, between the hips, that stands for the legs in collisions (m): standing, its bottom
is :data:`MAX_STEP` above the ground, so lower obstacles are stepped over or onto and higher ones stop
the robot."""
BODY_FRICTION = 0.5
"""Friction of the trunk (multiplied by the other body's)."""

_HALF_HEIGHT = BODY_SIZE[2] / 2.0
_RAY_START = 0.005  # rays start this far below the trunk so they never hit it
_RAY_LENGTH = LEG_REACH - _RAY_START
_STAND_LEG = LEG_REST - STANDING_COMPRESSION
_HIP_OFFSETS = tuple((x, y, -_HALF_HEIGHT) for x, y in HIPS)
_TRUNK_INERTIA = tuple(
    MASS / 12.0 * (BODY_SIZE[(k + 1) % 3] ** 2 + BODY_SIZE[(k + 2) % 3] ** 2) for k in range(3)
)
_SHARE = MASS / 4.0 * TRACTION_GAIN  # traction per unit velocity error of one foot (N s/m)
_LEGS = LegModel(
    _HIP_OFFSETS,
    share=_SHARE,
    stiffness=LEG_STIFFNESS,
    damping=LEG_DAMPING,
    max_push=LEG_MAX_FORCE,
    rest=LEG_REST,
    min_length=LEG_MIN,
    reach=LEG_REACH,
    ray_start=_RAY_START,
    ray_length=_RAY_LENGTH,
    traction_max=TRACTION_MAX,
    default_friction=OBJECT_FRICTION,
)
"""The leg forces of one physics step: the formulas of this module's docstring."""


class Spot(RobotBody):
    """A Spot-sized legged robot (reduced-order model, see the module docstring).

    The robot is created unspawned; :meth:`spawn` puts it in a world.
    """

    name = "spot"
    radius = 0.6
    size = (BODY_SIZE[0], BODY_SIZE[1], _STAND_LEG + BODY_SIZE[2])
    max_velocity = (1.5, 0.5, 1.5)
    standing_height = _STAND_LEG + _HALF_HEIGHT
    """Height of the base origin (trunk centre) above flat ground when standing (m)."""

    def __init__(self) -> None:
        super().__init__()
        self.camera_to_base = camera_mount((BODY_SIZE[0] / 2.0 - 0.05, 0.0, 0.6 - self.standing_height))
        self._legs = [0.0] * 4
        self._ray_from = [(x, y, -_HALF_HEIGHT - _RAY_START) for x, y in HIPS]
        self._ray_to = [(x, y, -_HALF_HEIGHT - LEG_REACH) for x, y in HIPS]
        self._friction: dict[int, float] = {}

    # ------------------------------------------------------------------ lifecycle

    def spawn(self, world: World, position: Sequence[float], yaw: float) -> None:
        """Place the robot standing at rest above the ground point `position`, heading `yaw`.

        The ground is probed below the four hips (where a hip finds none, the height of `position` is
        used); the trunk is put level at the standing height above their mean, where the stance
        (level-keeping leg lengths) holds it, so it starts in equilibrium on flat ground and on a
        uniform slope. The command is reset to 0.
        """
        if self.body >= 0:
            raise RuntimeError("this Spot is already spawned; remove() it first")
        c = world.client
        x, y, z = (float(v) for v in position)
        cy, sy = math.cos(yaw), math.sin(yaw)
        grounds = []
        for hx, hy in HIPS:
            px, py = x + cy * hx - sy * hy, y + sy * hx + cy * hy
            info, height = world.surface_below((px, py, z + 0.3), depth=0.8)
            grounds.append(height if info is not None else z)
        ground = sum(grounds) / len(grounds)
        shape = c.createCollisionShapeArray(
            [pybullet.GEOM_BOX, pybullet.GEOM_BOX],
            halfExtents=[[s / 2.0 for s in BODY_SIZE], [s / 2.0 for s in LEG_ZONE]],
            collisionFramePositions=[[0.0, 0.0, 0.0], [0.0, 0.0, -_HALF_HEIGHT - LEG_ZONE[2] / 2.0]],
        )
        self.body = c.createMultiBody(
            baseMass=MASS,
            baseCollisionShapeIndex=shape,
            basePosition=(x, y, ground + self.standing_height),
            baseOrientation=(0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)),
        )
        c.changeDynamics(
            self.body,
            -1,
            lateralFriction=BODY_FRICTION,
            restitution=0.0,
            linearDamping=0.0,
            angularDamping=0.0,
            localInertiaDiagonal=_TRUNK_INERTIA,  # the trunk box's (the leg zone has no mass of its own)
        )
        self._world = world
        self._friction = {body: info.friction for body, info in world.bodies.items()}
        self._command = (0.0, 0.0, 0.0)
        self._legs = [0.0] * 4
        # Bound client methods: the BulletClient builds a partial on every attribute access.
        self._state = c.getBasePositionAndOrientation
        self._velocity = c.getBaseVelocity
        self._rays = c.rayTestBatch
        self._force = c.applyExternalForce
        self._torque = c.applyExternalTorque

    # ------------------------------------------------------------------ control

    def set_command(self, vx: float, vy: float, wz: float) -> None:
        """Set the body-frame velocity target, clipped to :attr:`max_velocity`; held until the next call."""
        self._command = clip_command(vx, vy, wz, self.max_velocity)

    def before_step(self) -> None:
        """Cast the leg rays and apply the legs' spring, damping and traction forces for one step.

        The forces are the module's formulas, computed by :class:`navverse.sim._legs.LegModel` (native
        code, the same double-precision operations in the same order as in Python).
        """
        body = self.body
        state = self._state(body)
        hits = self._rays(self._ray_from, self._ray_to, parentObjectUniqueId=body, parentLinkIndex=-1)
        out = _LEGS.forces(state, self._velocity(body), self._command, hits, self._friction, body)
        self._legs = out[6:]
        self._force(body, -1, out[:3], state[0], pybullet.WORLD_FRAME)
        self._torque(body, -1, out[3:6], pybullet.WORLD_FRAME)

    # ------------------------------------------------------------------ state

    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Trunk centre (3,) and orientation quaternion ``[x, y, z, w]`` (4,) in the world frame."""
        position, orientation = self._state(self.body)
        return np.array(position), np.array(orientation)

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Trunk linear (3,) and angular (3,) velocity in the world frame."""
        linear, angular = self._velocity(self.body)
        return np.array(linear), np.array(angular)

    def leg_forces(self) -> np.ndarray:
        """Push (N) of each leg (FL, FR, RL, RR) at the last :meth:`before_step`; 0 for a leg in the air."""
        return np.array(self._legs)

    def is_ground_contact(self, contact: Contact) -> bool:
        """Always False: the legs have no collision geometry, so every contact is the trunk colliding."""
        return False
