"""People on the test street: seeded, off the road, out of sight of a start, always on a trip."""

from __future__ import annotations

import numpy as np
import pytest

from navverse import nav
from navverse.dynamics.pedestrians import Pedestrians, PedestrianSettings, WalkableAreas
from tests.navverse.dynamics.test_crowd import AREAS, _street

BUSY = PedestrianSettings(density=40.0, trip_length=(5.0, 30.0))


@pytest.fixture(scope="module")
def street() -> nav.PathFinder:
    return _street()


def _tracks(people: Pedestrians, seconds: float, dt: float = 0.1) -> tuple[np.ndarray, np.ndarray]:
    """Positions (T, N, 3) and areas (T, N) of the people over `seconds`."""
    positions, areas = [], []
    for _ in range(round(seconds / dt)):
        state = people.step(dt)
        positions.append(state.positions[people.people])
        areas.append(state.areas[people.people])
    return np.array(positions), np.array(areas)


def test_the_walkable_areas_are_those_named(street: nav.PathFinder) -> None:
    sidewalks = WalkableAreas(street, ("sidewalk",))
    assert 0.75 * (2 * 40 * 4) < sidewalks.area_m2 <= 2 * 40 * 4  # the navmesh keeps off the edges
    points = sidewalks.draw(np.random.default_rng(0), 500)
    # On the sidewalks, to within the navmesh's voxels at their border with the road.
    assert (np.abs(points[:, 1]) >= 6.0 - 0.5).all() and (np.abs(points[:, 1]) <= 10.0).all()
    assert WalkableAreas(street, ("no such area",)).draw(np.random.default_rng(0), 5).shape == (0, 3)


def test_the_density_sets_how_many_people_walk(street: nav.PathFinder) -> None:
    people = Pedestrians(street, BUSY, seed=1)
    sidewalks = WalkableAreas(street, ("sidewalk",)).area_m2
    assert people.walkable_area_m2 > sidewalks  # and the crosswalk
    assert len(people.people) == round(BUSY.density * people.walkable_area_m2 / 1000)
    capped = Pedestrians(street, PedestrianSettings(density=40.0, max_people=3), seed=1)
    assert len(capped.people) == 3


def test_the_same_seed_gives_the_same_people_on_the_same_trips(street: nav.PathFinder) -> None:
    first, _ = _tracks(Pedestrians(street, BUSY, seed=3), 20.0)
    again, _ = _tracks(Pedestrians(street, BUSY, seed=3), 20.0)
    other, _ = _tracks(Pedestrians(street, BUSY, seed=4), 20.0)
    assert first.tobytes() == again.tobytes()
    assert first.shape != other.shape or not np.allclose(first, other)


def test_people_keep_off_the_road_and_keep_walking(street: nav.PathFinder) -> None:
    people = Pedestrians(street, BUSY, seed=5)
    positions, areas = _tracks(people, 60.0)
    assert AREAS["road"] not in set(areas.ravel().tolist())
    crossing = np.abs(positions[..., 1]) < 6.0 - 0.05
    assert (np.abs(positions[..., 0][crossing]) <= 2.0 + 1e-3).all()  # only on the crosswalk
    walked = np.linalg.norm(np.diff(positions[..., :2], axis=0), axis=-1).sum(axis=0)
    assert (walked > 30.0).all()  # nobody stands still for a minute: trips follow trips


def test_nobody_starts_where_the_start_sees(street: nav.PathFinder) -> None:
    def seen_from_the_north(points: np.ndarray) -> np.ndarray:
        return points[:, 1] > 0.0

    people = Pedestrians(street, BUSY, seed=6, visible=seen_from_the_north)
    state = people.crowd.state()
    assert len(people.people) > 5
    assert (state.positions[people.people, 1] < 0.0).all()
