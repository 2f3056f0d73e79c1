"""Dynamics in an environment: made anew for every episode, stepped with the physics, drawn by the camera.

:class:`EpisodeDynamics` is what :class:`~navverse.env.NavVerseEnv` holds when it runs with dynamics
(``dynamics="pedestrians"`` or ``"full"``). At each episode's start it removes the last episode's bodies,
makes the scene's :class:`~navverse.dynamics.scene_dynamics.SceneDynamics` from the episode's seed,
keeps people out of sight of the robot's start (none starts where its legs, chest or head can be seen
from the robot's camera height, however far), gives every person and car a kinematic body
(:class:`~navverse.dynamics.bodies.MovingBodies`, stepped as an observer of the simulator) and, before
every frame, places them in the renderer: people in one of four outfits, cars as sedans; their
semantic ids are :data:`PERSON_ID_BASE` + index and :data:`CAR_ID_BASE` + index (categories
``person`` and ``car``).
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import numpy as np

from navverse.dynamics.bodies import MovingBodies
from navverse.dynamics.scene_dynamics import DynamicsSettings, DynamicState, SceneDynamics
from navverse.dynamics.shapes import PERSON_OUTFITS, car_mesh, person_mesh
from navverse.nav.pathfinder import PathFinder
from navverse.sim.render import SceneRenderer
from navverse.sim.simulator import Simulator

__all__ = [
    "CAR_ID_BASE",
    "PERSON_ID_BASE",
    "BodyPainter",
    "EpisodeDynamics",
    "episode_seed",
    "yaw_transforms",
]

PERSON_ID_BASE = 1 << 24
"""Semantic id of person ``i``: ``PERSON_ID_BASE + i`` (above every object and storefront id)."""
CAR_ID_BASE = PERSON_ID_BASE + (1 << 16)
"""Semantic id of moving car ``i``: ``CAR_ID_BASE + i``."""
_EYE_HEIGHT = 0.6
_BODY_POINTS = (0.3, 1.0, 1.6)  # a person is in sight when one of these heights above its feet is


def episode_seed(seed: int, episode_id: str) -> int:
    """The dynamics seed of an episode: a hash of the run's seed and the episode id."""
    digest = hashlib.sha256(f"dynamics:{seed}:{episode_id}".encode()).digest()
    return int.from_bytes(digest[:8], "little")


def yaw_transforms(positions: np.ndarray, yaws: np.ndarray) -> np.ndarray:
    """Rigid transforms ``(K, 4, 4)``: rotation by each yaw about +z, then translation to its position."""
    c, s = np.cos(yaws), np.sin(yaws)
    out = np.zeros((len(positions), 4, 4))
    out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1] = c, -s, s, c
    out[:, 2, 2] = out[:, 3, 3] = 1.0
    out[:, :3, 3] = positions
    return out


class BodyPainter:
    """Draws a :class:`~navverse.dynamics.scene_dynamics.DynamicState` in a renderer: people in one of
    :data:`PERSON_OUTFITS` each (by index), cars as sedans, with their semantic ids.

    Parameters
    ----------
    renderer : SceneRenderer
        The camera; the shapes are added to it once, here.
    max_people, max_cars : int, keyword-only
        The most people and cars a state will hold.
    """

    def __init__(self, renderer: SceneRenderer, *, max_people: int, max_cars: int) -> None:
        self.renderer = renderer
        per_outfit = math.ceil(max(1, max_people) / len(PERSON_OUTFITS))
        self._people = [
            renderer.add_body_shape(person_mesh(k), max_bodies=per_outfit) for k in range(len(PERSON_OUTFITS))
        ]
        self._car = renderer.add_body_shape(car_mesh(), max_bodies=max_cars) if max_cars > 0 else None

    def show(self, state: DynamicState | None) -> None:
        """Place everything of `state` in the renderer (nothing for None)."""
        if state is None:
            self.renderer.place_bodies([], np.zeros((0, 4, 4)), [])
            return
        people = len(state.people)
        shapes = [self._people[i % len(self._people)] for i in range(people)]
        transforms = [yaw_transforms(state.people, state.people_headings)]
        ids = list(PERSON_ID_BASE + np.arange(people))
        if self._car is not None and len(state.cars):
            shapes += [self._car] * len(state.cars)
            transforms.append(yaw_transforms(state.cars, state.car_headings))
            ids += list(CAR_ID_BASE + np.arange(len(state.cars)))
        self.renderer.place_bodies(shapes, np.concatenate(transforms), ids)

    @staticmethod
    def categories(state: DynamicState | None) -> dict[int, str]:
        """Semantic id -> category (``person``, ``car``) of everything in `state`."""
        if state is None:
            return {}
        found = {PERSON_ID_BASE + i: "person" for i in range(len(state.people))}
        found.update({CAR_ID_BASE + i: "car" for i in range(len(state.cars))})
        return found


class EpisodeDynamics:
    """The people and cars of an environment's episodes.

    Parameters
    ----------
    scene_dir : path
        The built scene.
    finder : PathFinder
        Its navmesh, areas named.
    settings : DynamicsSettings
        What moves (mode ``off``: nothing, and nothing is made).
    renderer : SceneRenderer
        The camera that shows them.
    """

    def __init__(
        self, scene_dir: str | Path, finder: PathFinder, settings: DynamicsSettings, renderer: SceneRenderer
    ) -> None:
        self.scene_dir = Path(scene_dir)
        self.finder = finder
        self.settings = settings
        self.renderer = renderer
        self.dynamics: SceneDynamics | None = None
        self.bodies: MovingBodies | None = None
        self._painter: BodyPainter | None = None

    @property
    def active(self) -> bool:
        """Whether anything moves."""
        return self.settings.mode != "off"

    def start(self, sim: Simulator, *, seed: int) -> None:
        """Begin an episode whose robot has just been spawned: new people and cars from `seed`."""
        self.stop(sim)
        if not self.active:
            return
        if self._painter is None:
            cars = self.settings.max_cars if self.settings.mode == "full" else 0
            self._painter = BodyPainter(
                self.renderer, max_people=self.settings.people.max_people, max_cars=cars
            )
        eye = np.asarray(sim.pose().position, dtype=float) + np.array([0.0, 0.0, _EYE_HEIGHT])

        def visible(points: np.ndarray) -> np.ndarray:
            feet = np.asarray(points, dtype=float).reshape(-1, 3)
            seen = np.zeros(len(feet), dtype=bool)
            for height in _BODY_POINTS:
                seen |= self.renderer.sees(eye, feet + np.array([0.0, 0.0, height]))
            return seen

        self.dynamics = SceneDynamics(
            self.scene_dir,
            self.finder,
            self.settings,
            seed=seed,
            robot_radius=sim.robot.radius,
            visible=visible,
        )
        self.bodies = MovingBodies(sim.world, self.dynamics)
        self.bodies.attach(sim)
        self.show()

    def stop(self, sim: Simulator) -> None:
        """Remove the current episode's bodies from the world and the camera."""
        if self.bodies is not None:
            if self.bodies in sim.observers:
                sim.observers.remove(self.bodies)
            for body in [*self.bodies.people, *self.bodies.cars]:
                sim.world.client.removeBody(body)
                sim.world.bodies.pop(body, None)
        self.bodies = None
        self.dynamics = None
        if self._painter is not None:
            self._painter.show(None)

    def show(self) -> None:
        """Place the people and cars where they are now in the renderer."""
        if self._painter is not None and self.bodies is not None:
            self._painter.show(self.bodies.state)

    def semantic_categories(self) -> dict[int, str]:
        """Semantic id -> category of the people and cars of the current episode."""
        return BodyPainter.categories(None if self.bodies is None else self.bodies.state)
