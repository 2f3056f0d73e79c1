"""People as kinematic PyBullet bodies in a world: the robot's collisions name them."""

from __future__ import annotations

import numpy as np
import pytest

from navverse import nav
from navverse.dynamics.bodies import PERSON_HEIGHT, MovingBodies
from navverse.dynamics.pedestrians import PedestrianSettings
from navverse.dynamics.scene_dynamics import DynamicsSettings, SceneDynamics
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.sim.embodiments import make_embodiment
from navverse.sim.simulator import Simulator
from navverse.sim.world import World
from tests.navverse.scene.conftest import build_scene

ROOM = DynamicsSettings(mode="pedestrians", people=PedestrianSettings(density=60.0, areas=("floor",),
                                                                      trip_length=(2.0, 8.0)))  # fmt: skip


@pytest.fixture(scope="module")
def room():
    scene = build_scene()
    return scene, build_scene_navmesh(scene, nav.INDOOR, jobs=1)


def _simulator(scene) -> Simulator:
    world = World(scene, collision_cache=None)
    sim = Simulator(world, make_embodiment("spot"))
    sim.spawn((2.0, 4.0, 0.0), 0.0)
    return sim


def test_every_person_is_a_body_where_the_crowd_puts_it(room, tmp_path) -> None:
    scene, finder = room
    sim = _simulator(scene)
    bodies = MovingBodies(sim.world, SceneDynamics(tmp_path, finder, ROOM, seed=0))
    assert len(bodies.people) == len(bodies.state.people) > 2 and bodies.cars == []
    for body, foot in zip(bodies.people, bodies.state.people, strict=True):
        position, _ = sim.world.client.getBasePositionAndOrientation(body)
        np.testing.assert_allclose(position, foot + np.array([0.0, 0.0, PERSON_HEIGHT / 2.0]), atol=1e-6)
        assert sim.world.bodies[body].category == "person"
    sim.world.close()


def test_as_an_observer_it_steps_the_crowd_with_the_simulation(room, tmp_path) -> None:
    scene, finder = room
    sim = _simulator(scene)
    bodies = MovingBodies(sim.world, SceneDynamics(tmp_path, finder, ROOM, seed=0), period=0.1)
    bodies.attach(sim)
    start = bodies.state.people.copy()
    while sim.time < 2.0:
        sim.tick(0.0, 0.0, 0.0)
    assert bodies.state.time == pytest.approx(2.0, abs=0.11)
    assert np.linalg.norm(bodies.state.people - start, axis=1).max() > 0.5  # they walked
    sim.world.close()


def test_a_person_walked_into_the_robot_is_a_collision_with_a_person(room, tmp_path) -> None:
    scene, finder = room
    sim = _simulator(scene)
    bodies = MovingBodies(sim.world, SceneDynamics(tmp_path, finder, ROOM, seed=0))
    state = bodies.state
    robot = sim.pose().position
    state.people[0] = (robot[0] + 0.2, robot[1], 0.0)  # into the robot's body
    bodies.place(state)
    for _ in range(5):
        sim.tick(0.0, 0.0, 0.0)
    assert any(c.body.category == "person" for c in sim.collisions)
    sim.world.close()
