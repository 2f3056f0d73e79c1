"""Pedestrians of DetourCrowd on a street: sidewalks, a road between them and one crosswalk."""

from __future__ import annotations

import numpy as np
import pytest

from navverse import nav
from navverse.dynamics.crowd import PEDESTRIAN, Crowd, TargetState, WalkerKind

AREAS = {"crosswalk": 1, "road": 6, "sidewalk": 7}
ROAD_HALF_WIDTH = 6.0
CROSSWALK_HALF_WIDTH = 2.0


def _quad(x0: float, y0: float, x1: float, y1: float, start: int) -> tuple[list, list]:
    vertices = [(x0, y0, 0.0), (x1, y0, 0.0), (x1, y1, 0.0), (x0, y1, 0.0)]
    return vertices, [(start, start + 1, start + 2), (start, start + 2, start + 3)]


def _street() -> nav.PathFinder:
    """40 m of street: a sidewalk each side (4 m), a 12 m road, a 4 m crosswalk across it at x = 0."""
    parts = [
        ((-20, -10, 20, -6), "sidewalk"),
        ((-20, 6, 20, 10), "sidewalk"),
        ((-20, -6, -2, 6), "road"),
        ((2, -6, 20, 6), "road"),
        ((-2, -6, 2, 6), "crosswalk"),
    ]
    vertices, faces, areas = [], [], []
    for box, area in parts:
        v, f = _quad(*box, start=len(vertices))
        vertices += v
        faces += f
        areas += [AREAS[area]] * 2
    finder = nav.build(np.array(vertices, float), np.array(faces), nav.OUTDOOR, area_types=np.array(areas))
    finder.name_areas(AREAS)
    return finder


@pytest.fixture(scope="module")
def street() -> nav.PathFinder:
    return _street()


def _walk(crowd: Crowd, steps: int, dt: float = 0.1) -> list:
    states = []
    for _ in range(steps):
        crowd.step(dt)
        states.append(crowd.state())
    return states


def test_a_pedestrian_crosses_the_road_only_on_the_crosswalk(street: nav.PathFinder) -> None:
    crowd = Crowd(street, [PEDESTRIAN], max_agents=4)
    agent = crowd.add((-15.0, -8.0, 0.0), "pedestrian")
    assert agent is not None and crowd.walk_to(agent, (15.0, 8.0, 0.0))
    states = _walk(crowd, 500)
    track = np.array([s.positions[agent] for s in states])
    areas = {int(s.areas[agent]) for s in states}
    assert np.linalg.norm(track[-1, :2] - (15.0, 8.0)) < 0.5  # it arrived
    assert AREAS["road"] not in areas and AREAS["crosswalk"] in areas
    on_road_band = np.abs(track[:, 1]) < ROAD_HALF_WIDTH - 0.05
    assert on_road_band.any() and (np.abs(track[on_road_band, 0]) <= CROSSWALK_HALF_WIDTH + 1e-3).all()
    speeds = np.linalg.norm(np.array([s.velocities[agent] for s in states])[:, :2], axis=1)
    assert speeds.max() <= PEDESTRIAN.max_speed + 1e-3


def test_a_walker_allowed_on_the_road_takes_the_short_way(street: nav.PathFinder) -> None:
    jaywalker = WalkerKind(name="jaywalker")
    crowd = Crowd(street, [PEDESTRIAN, jaywalker], max_agents=4)
    agent = crowd.add((-15.0, -8.0, 0.0), "jaywalker")
    assert crowd.walk_to(agent, (-15.0, 8.0, 0.0))
    states = _walk(crowd, 200)
    assert AREAS["road"] in {int(s.areas[agent]) for s in states}
    assert np.abs(np.array([s.positions[agent][0] for s in states]) + 15.0).max() < 1.0


def test_the_same_agents_and_targets_give_the_same_trajectories(street: nav.PathFinder) -> None:
    def run() -> bytes:
        crowd = Crowd(street, [PEDESTRIAN], max_agents=16)
        rng = np.random.default_rng(7)
        for _ in range(12):
            side = rng.choice([-8.0, 8.0])
            agent = crowd.add((rng.uniform(-18, 18), side, 0.0), "pedestrian")
            crowd.walk_to(agent, (rng.uniform(-18, 18), -side, 0.0))
        return b"".join(s.positions.tobytes() + s.velocities.tobytes() for s in _walk(crowd, 150))

    assert run() == run()


def test_pedestrians_meeting_head_on_pass_without_overlapping(street: nav.PathFinder) -> None:
    crowd = Crowd(street, [PEDESTRIAN], max_agents=4)
    a = crowd.add((-10.0, -8.0, 0.0), "pedestrian")
    b = crowd.add((10.0, -8.0, 0.0), "pedestrian")
    crowd.walk_to(a, (10.0, -8.0, 0.0))
    crowd.walk_to(b, (-10.0, -8.0, 0.0))
    states = _walk(crowd, 300)
    gaps = [np.linalg.norm(s.positions[a][:2] - s.positions[b][:2]) for s in states]
    assert min(gaps) > 1.8 * PEDESTRIAN.radius
    assert states[-1].positions[a][0] > 9.0 and states[-1].positions[b][0] < -9.0


def test_a_body_standing_in_the_way_is_walked_around_not_through(street: nav.PathFinder) -> None:
    robot_kind = WalkerKind(name="robot", radius=0.45, max_speed=1.5)
    crowd = Crowd(street, [PEDESTRIAN, robot_kind], max_agents=4)
    robot = crowd.add((0.0, 8.0, 0.0), "robot")
    person = crowd.add((-10.0, 8.0, 0.0), "pedestrian")
    assert crowd.move_at(robot, (0.0, 0.0, 0.0))  # it stands: the physics moves it, not the crowd
    crowd.walk_to(person, (10.0, 8.0, 0.0))
    states = _walk(crowd, 300)
    gaps = [np.linalg.norm(s.positions[person][:2] - s.positions[robot][:2]) for s in states]
    assert min(gaps) > 0.9 * (PEDESTRIAN.radius + robot_kind.radius)
    assert np.linalg.norm(states[-1].positions[robot][:2] - (0.0, 8.0)) < 0.05  # not pushed away
    assert states[-1].positions[person][0] > 9.0
    assert crowd.target_state(robot) == TargetState.VELOCITY


def test_a_placed_agent_is_where_it_was_put(street: nav.PathFinder) -> None:
    crowd = Crowd(street, [PEDESTRIAN], max_agents=2)
    agent = crowd.add((0.0, -8.0, 0.0), "pedestrian")
    assert crowd.place(agent, (5.0, 8.5, 0.0))
    np.testing.assert_allclose(crowd.state().positions[agent][:2], (5.0, 8.5), atol=1e-4)
    assert not crowd.place(agent, (100.0, 100.0, 0.0))  # off the mesh


def test_bad_requests_are_refused(street: nav.PathFinder) -> None:
    crowd = Crowd(street, [PEDESTRIAN], max_agents=1)
    assert crowd.add((0.0, 0.0, 0.0), "pedestrian") is not None  # the crosswalk is allowed
    assert crowd.add((0.0, 8.0, 0.0), "pedestrian") is None  # full
    with pytest.raises(ValueError, match="unknown kind of walker 'car'"):
        crowd.add((0.0, 8.0, 0.0), "car")
    with pytest.raises(ValueError, match="no such crowd agent"):
        crowd.walk_to(5, (0.0, 8.0, 0.0))
    with pytest.raises(ValueError, match="finite point"):
        crowd.walk_to(0, (np.nan, 0.0, 0.0))
    with pytest.raises(ValueError, match="positive time"):
        crowd.step(0.0)
    road_only = Crowd(street, [PEDESTRIAN], max_agents=2)
    assert road_only.add((-10.0, 0.0, 0.0), "pedestrian") is None  # on the road, 4 m from any allowed area


def test_a_navmesh_without_area_names_cannot_keep_walkers_off_roads(street: nav.PathFinder) -> None:
    unnamed = nav.PathFinder.from_bytes(street.to_bytes())
    with pytest.raises(ValueError, match="names no areas"):
        Crowd(unnamed, [PEDESTRIAN], max_agents=2)
    Crowd(unnamed, [WalkerKind(name="anyone")], max_agents=2)


LONG_WALK = """
import numpy as np
from navverse import nav
from navverse.dynamics.crowd import Crowd, WalkerKind

# A 1.2 km strip whose area changes every 2 m: a walk along it crosses ~600 polygons, more than the
# longest corridor DetourCrowd keeps (256).
vertices, faces, areas = [], [], []
for i in range(600):
    x = 2.0 * i
    start = len(vertices)
    vertices += [(x, 0.0, 0.0), (x + 2.0, 0.0, 0.0), (x + 2.0, 3.0, 0.0), (x, 3.0, 0.0)]
    faces += [(start, start + 1, start + 2), (start, start + 2, start + 3)]
    areas += [1 + i % 2] * 2
finder = nav.build(np.array(vertices), np.array(faces), nav.OUTDOOR, area_types=np.array(areas))
crowd = Crowd(finder, [WalkerKind(name="walker", max_speed=3.0)], max_agents=1)
agent = crowd.add((2.0, 1.5, 0.0), "walker")
assert crowd.walk_to(agent, (1195.0, 1.5, 0.0))
for _ in range(200):
    crowd.step(0.1)
x = crowd.state().positions[agent][0]
assert x > 40.0, x
print("walked", round(x, 1))
"""


def test_a_walk_longer_than_a_corridor_holds_does_not_abort(tmp_path) -> None:
    import subprocess
    import sys

    script = tmp_path / "long_walk.py"
    script.write_text(LONG_WALK)
    result = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "walked" in result.stdout
