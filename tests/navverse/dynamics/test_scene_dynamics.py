"""People and cars of a scene stepped together, the robot among them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from navverse.dynamics.pedestrians import PedestrianSettings
from navverse.dynamics.scene_dynamics import DynamicsSettings, SceneDynamics
from navverse.look.files import write_look
from navverse.look.scene_look import MapDetails, MarkedRoad
from navverse.look.settings import EVAL_LOOK
from tests.navverse.dynamics.test_crowd import _street

BUSY = PedestrianSettings(density=40.0, trip_length=(5.0, 30.0))


@pytest.fixture(scope="module")
def scene(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, object]:
    """The test street with its road in a look, as a built scene has it."""
    scene_dir = tmp_path_factory.mktemp("street")
    road = MarkedRoad(((-20.0, 0.0), (20.0, 0.0)), 12.0, 2, False, "residential")
    write_look(scene_dir / "look.json", EVAL_LOOK, MapDetails({}, [road]), geometry_sha256="0" * 64)
    return scene_dir, _street()


def _run(dynamics: SceneDynamics, seconds: float, robot=None) -> list:
    states = []
    for _ in range(round(seconds / 0.1)):
        if robot is not None:
            dynamics.place_robot(np.asarray(robot, float), np.zeros(3))
        states.append(dynamics.step(0.1))
    return states


def test_off_moves_nothing(scene) -> None:
    state = SceneDynamics(*scene, DynamicsSettings(), seed=0).step(0.1)
    assert state.people.shape == (0, 3) and state.cars.shape == (0, 3)


def test_pedestrians_mode_has_people_and_no_cars(scene) -> None:
    states = _run(SceneDynamics(*scene, DynamicsSettings(mode="pedestrians", people=BUSY), seed=0), 5.0)
    assert len(states[-1].people) > 5 and len(states[-1].cars) == 0
    assert states[-1].time == pytest.approx(5.0)


def test_full_mode_drives_cars_on_the_road_and_is_seeded(scene) -> None:
    settings = DynamicsSettings(mode="full", people=BUSY, cars_per_km=100.0)
    first = _run(SceneDynamics(*scene, settings, seed=2), 20.0)
    again = _run(SceneDynamics(*scene, settings, seed=2), 20.0)
    assert len(first[-1].cars) == 4  # 100 per km of its 40 m road
    assert all(a.cars.tobytes() == b.cars.tobytes() and a.people.tobytes() == b.people.tobytes()
               for a, b in zip(first, again, strict=True))  # fmt: skip
    cars = np.concatenate([s.cars for s in first])
    assert (np.abs(cars[:, 1]) < 6.0).all()  # on the carriageway
    people = np.concatenate([s.people for s in first])
    on_road = np.abs(people[:, 1]) < 6.0 - 0.05
    assert on_road.any() and (np.abs(people[on_road, 0]) <= 2.0 + 1e-3).all()  # crossing on the crosswalk


def test_people_keep_clear_of_the_robot(scene) -> None:
    robot = (0.0, 8.0, 0.0)
    dynamics = SceneDynamics(
        *scene, DynamicsSettings(mode="pedestrians", people=BUSY), seed=3, robot_radius=0.45
    )
    states = _run(dynamics, 30.0, robot=robot)
    gaps = np.concatenate([np.linalg.norm(s.people[:, :2] - robot[:2], axis=1) for s in states[20:]])
    assert gaps.min() > 0.8 * (0.45 + 0.3)


def test_an_unknown_mode_is_refused() -> None:
    with pytest.raises(ValueError, match="unknown dynamics 'crowds'"):
        DynamicsSettings(mode="crowds")
