"""The people and cars of a :class:`~navverse.dynamics.scene_dynamics.SceneDynamics` as PyBullet bodies.

:class:`MovingBodies` gives every person a capsule and every moving car a box in a
:class:`~navverse.sim.world.World`: kinematic bodies (mass 0, placed each dynamics step), so the robot
collides with them as with any static body and its collision log names them (``kind="object"``,
``category`` ``person`` or ``car``). Used as an observer of a
:class:`~navverse.sim.simulator.Simulator`, it steps the dynamics every ``period`` seconds of simulated
time, first telling the crowd where the robot is and how fast it goes.

It works on the world from outside (its client and its table of bodies), so the world and the
simulator, which episode verification runs, are unchanged by it.
"""

from __future__ import annotations

import math

import numpy as np
import pybullet

from navverse.dynamics.scene_dynamics import DynamicState, SceneDynamics
from navverse.dynamics.traffic import CAR_LENGTH
from navverse.sim.simulator import Simulator
from navverse.sim.world import OBJECT_FRICTION, BodyInfo, World

__all__ = ["CAR_SIZE", "PERSON_HEIGHT", "PERSON_RADIUS", "MovingBodies"]

PERSON_RADIUS = 0.3
PERSON_HEIGHT = 1.7
CAR_SIZE = (CAR_LENGTH, 1.8, 1.5)
PERSON = BodyInfo("object", category="person", friction=OBJECT_FRICTION)
CAR = BodyInfo("object", category="car", friction=OBJECT_FRICTION)
_PARKED_AWAY = (0.0, 0.0, -1000.0)


def _yaw_quaternion(yaw: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


class MovingBodies:
    """Kinematic bodies of a scene's people and cars in a world.

    Parameters
    ----------
    world : World
        Where they stand.
    dynamics : SceneDynamics
        What moves them.
    period : float, keyword-only
        Simulated seconds between two dynamics steps (the crowd's rate; the bodies stay put between).
    """

    def __init__(self, world: World, dynamics: SceneDynamics, *, period: float = 0.1) -> None:
        if not period > 0.0:
            raise ValueError(f"the dynamics period must be positive, got {period}")
        self.world = world
        self.dynamics = dynamics
        self.period = float(period)
        self.state: DynamicState | None = None
        self._since = 0.0
        self._last_time: float | None = None
        c = world.client
        state = dynamics.current()
        capsule = c.createCollisionShape(
            pybullet.GEOM_CAPSULE, radius=PERSON_RADIUS, height=PERSON_HEIGHT - 2 * PERSON_RADIUS
        )
        box = c.createCollisionShape(pybullet.GEOM_BOX, halfExtents=[s / 2.0 for s in CAR_SIZE])
        self.people = [self._body(capsule, PERSON) for _ in range(len(state.people))]
        self.cars = [self._body(box, CAR) for _ in range(len(state.cars))]
        self.place(state)

    def _body(self, shape: int, info: BodyInfo) -> int:
        body = self.world.client.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=shape,
                                                 basePosition=_PARKED_AWAY)  # fmt: skip
        self.world.bodies[body] = info
        return body

    def place(self, state: DynamicState) -> None:
        """Put every body where `state` says (a person's capsule stands on its feet, a car on the road)."""
        reset = self.world.client.resetBasePositionAndOrientation
        for body, foot, yaw in zip(self.people, state.people, state.people_headings, strict=True):
            reset(body, (foot[0], foot[1], foot[2] + PERSON_HEIGHT / 2.0), _yaw_quaternion(float(yaw)))
        for body, centre, yaw in zip(self.cars, state.cars, state.car_headings, strict=True):
            reset(body, (centre[0], centre[1], centre[2] + CAR_SIZE[2] / 2.0), _yaw_quaternion(float(yaw)))
        self.state = state

    def __call__(self, sim: Simulator) -> None:
        """Observer of a simulator's ticks: every `period`, tell the crowd about the robot, step, place."""
        now = sim.time
        self._since += 0.0 if self._last_time is None else now - self._last_time
        self._last_time = now
        if self._since + 1e-9 < self.period:
            return
        self._since -= self.period
        pose = sim.pose()
        linear, _ = sim.robot.base_velocity()
        self.dynamics.place_robot(np.asarray(pose.position, float), np.asarray(linear, float))
        self.place(self.dynamics.step(self.period))

    def attach(self, sim: Simulator) -> None:
        """Start following a simulator's ticks."""
        if self not in sim.observers:
            sim.observers.append(self)
