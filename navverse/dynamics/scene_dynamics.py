"""People and cars of one built scene, stepped together, with the robot among them.

:class:`SceneDynamics` is what the simulator holds when an episode runs with dynamics: the scene's
pedestrians (:mod:`.pedestrians`, on its navmesh) and, in mode ``full``, its traffic (:mod:`.traffic`,
on the lanes of its street plan, halting for the people on crossings). The robot is a body of the
same crowd: each step it is placed where the physics put it, with its velocity, so people steer
round it (and wait where they cannot pass) as they do round each other. Everything is drawn from one
seed (an episode's), so two runs of an episode see the same crowd and the same traffic as long as
the robot moves the same way.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np

from navverse.dynamics.crowd import WalkerKind
from navverse.dynamics.pedestrians import Pedestrians, PedestrianSettings
from navverse.dynamics.streets import scene_streets
from navverse.dynamics.traffic import Traffic, lanes_of
from navverse.nav.pathfinder import PathFinder

__all__ = ["DYNAMICS_MODES", "DynamicState", "DynamicsSettings", "SceneDynamics"]

DynamicsMode = Literal["off", "pedestrians", "full"]
DYNAMICS_MODES: tuple[str, ...] = ("off", "pedestrians", "full")
"""``off``: the scene as published; ``pedestrians``: people on foot; ``full``: people and traffic."""


@dataclass(frozen=True)
class DynamicsSettings:
    """What moves in a scene besides the robot.

    Attributes
    ----------
    mode : {"off", "pedestrians", "full"}
        :data:`DYNAMICS_MODES`.
    people : PedestrianSettings
        Density and trips of the people.
    cars_per_km : float
        Moving cars per kilometre of road centerline (mode ``full``); 6 puts about 30 in a 500 m window
        of a dense city.
    max_cars : int
        The most moving cars in one scene.
    """

    mode: DynamicsMode = "off"
    people: PedestrianSettings = field(default_factory=PedestrianSettings)
    cars_per_km: float = 6.0
    max_cars: int = 60

    def __post_init__(self) -> None:
        if self.mode not in DYNAMICS_MODES:
            raise ValueError(f"unknown dynamics {self.mode!r}; choose from: {', '.join(DYNAMICS_MODES)}")
        if not self.cars_per_km >= 0.0 or self.max_cars < 0:
            raise ValueError("cars_per_km and max_cars must be 0 or more")


@dataclass(frozen=True)
class DynamicState:
    """Where everything that moves is after a step.

    Attributes
    ----------
    time : float
        Seconds since the dynamics began.
    people, cars : ndarray, shape (P, 3) / (C, 3)
        Positions (m): a person's feet on the navmesh, a car's centre on the road surface.
    people_headings, car_headings : ndarray, shape (P,) / (C,)
        Directions (radians from +x) they face.
    people_velocities : ndarray, shape (P, 3)
    car_speeds : ndarray, shape (C,)
    """

    time: float
    people: np.ndarray
    people_headings: np.ndarray
    people_velocities: np.ndarray
    cars: np.ndarray
    car_headings: np.ndarray
    car_speeds: np.ndarray


class SceneDynamics:
    """The people and cars of a scene, stepped with the robot among them.

    Parameters
    ----------
    scene_dir : path
        The built scene (its look gives the roads).
    finder : PathFinder
        Its navmesh, areas named (``load_scene_navmesh``).
    settings : DynamicsSettings
        What moves.
    seed : int, keyword-only
        The episode's seed.
    robot_radius : float, keyword-only
        The robot's footprint radius, for the others to keep clear of.
    visible : callable, optional, keyword-only
        ``visible(points (K, 3)) -> bool (K,)``: where nobody may start (seen from the robot's start).
    """

    def __init__(
        self,
        scene_dir: str | Path,
        finder: PathFinder,
        settings: DynamicsSettings,
        *,
        seed: int,
        robot_radius: float = 0.45,
        visible=None,
    ) -> None:
        self.settings = settings
        self._finder = finder
        self.time = 0.0
        self._robot: int | None = None
        self._robot_kind = WalkerKind(name="robot", radius=float(robot_radius), max_speed=2.0)
        self.pedestrians: Pedestrians | None = None
        self.traffic: Traffic | None = None
        self._headings = np.zeros(0)
        if settings.mode == "off":
            return
        seeds = np.random.SeedSequence(int(seed)).spawn(2)
        self.pedestrians = Pedestrians(
            finder,
            settings.people,
            seed=int(seeds[0].generate_state(1)[0]),
            visible=visible,
            others=[self._robot_kind],
        )
        if settings.mode == "full":
            plan = scene_streets(scene_dir, finder)
            lanes = lanes_of(plan.roads)
            road_km = (
                sum(
                    float(np.linalg.norm(np.diff(road.centerline, axis=0), axis=1).sum())
                    for road in plan.roads
                )
                / 1000.0
            )
            cars = min(settings.max_cars, round(settings.cars_per_km * road_km))
            self.traffic = Traffic(
                lanes, plan.crossings, cars=cars, seed=int(seeds[1].generate_state(1)[0]), height=self._ground
            )

    def _ground(self, points: np.ndarray) -> np.ndarray:
        """The navmesh's height under 2-D points (0 where there is none within reach)."""
        flat = np.column_stack([points, np.zeros(len(points))])
        ground = self._finder.snap_point(flat, max_vertical=5.0)
        return np.where(np.isfinite(ground[:, 2]), ground[:, 2], 0.0)

    def place_robot(self, position: np.ndarray, velocity: np.ndarray) -> None:
        """Tell the people where the robot is and how it moves (it joins the crowd the first time)."""
        if self.pedestrians is None:
            return
        crowd = self.pedestrians.crowd
        if self._robot is None:
            self._robot = crowd.add(position, self._robot_kind.name)
            if self._robot is None:
                return  # off the navmesh (on an object): the people do not see it this step
        elif not crowd.place(self._robot, position):
            return
        crowd.move_at(self._robot, velocity)

    def step(self, dt: float) -> DynamicState:
        """Advance everything by `dt` seconds; returns where everything is then."""
        self.time += dt
        crowd = self.pedestrians.step(dt) if self.pedestrians is not None else None
        people = self._people(crowd)
        traffic = self.traffic.step(dt, people=people[0][:, :2]) if self.traffic is not None else None
        return self._snapshot(people, traffic)

    def current(self) -> DynamicState:
        """Where everything is now, without a step."""
        crowd = self.pedestrians.crowd.state() if self.pedestrians is not None else None
        traffic = self.traffic.state() if self.traffic is not None else None
        return self._snapshot(self._people(crowd), traffic)

    def _people(self, crowd) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The people's positions, headings (a person standing keeps facing as it did) and velocities."""
        if crowd is None or self.pedestrians is None:
            return np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3))
        ids = self.pedestrians.people
        people, velocities = crowd.positions[ids], crowd.velocities[ids]
        if len(self._headings) != len(ids):
            self._headings = np.zeros(len(ids))
        moving = np.hypot(velocities[:, 0], velocities[:, 1]) > 0.05
        self._headings[moving] = np.arctan2(velocities[moving, 1], velocities[moving, 0])
        return people, self._headings.copy(), velocities

    def _snapshot(self, people, traffic) -> DynamicState:
        """The state of the people (as :meth:`_people` gives them) and of the traffic."""
        people, headings, velocities = people
        if traffic is None:
            cars, car_headings, speeds = np.zeros((0, 3)), np.zeros(0), np.zeros(0)
        else:
            cars = np.column_stack([traffic.positions, traffic.heights])
            car_headings, speeds = traffic.headings, traffic.speeds
        return DynamicState(self.time, people, headings, velocities, cars, car_headings, speeds)
