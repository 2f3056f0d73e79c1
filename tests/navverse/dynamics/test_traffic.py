"""Cars on a ring of streets: lanes from the roads, car following, stops for people on a crossing."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from navverse.dynamics.traffic import (
    CAR_LENGTH,
    SPEED_BY_HIGHWAY,
    STOP_BEFORE,
    RoadSpec,
    Traffic,
    lanes_of,
)

SIDE = 100.0


def _block() -> list[RoadSpec]:
    """Four two-way residential streets round a 100 m block, meeting at its corners."""
    corners = [(0.0, 0.0), (SIDE, 0.0), (SIDE, SIDE), (0.0, SIDE)]
    return [
        RoadSpec(np.array([corners[i], corners[(i + 1) % 4]]), width=6.5, highway="residential")
        for i in range(4)
    ]


def _run(traffic: Traffic, seconds: float, *, people=None, dt: float = 0.1) -> list:
    return [traffic.step(dt, people=people) for _ in range(round(seconds / dt))]


def test_a_two_way_road_has_a_lane_each_way_on_its_right() -> None:
    road = RoadSpec(np.array([(0.0, 0.0), (50.0, 0.0)]), width=6.5)
    forward, backward = lanes_of([road])
    assert forward.forward and not backward.forward
    assert forward.points[:, 1] == pytest.approx(-6.5 / 4) and backward.points[:, 1] == pytest.approx(6.5 / 4)
    assert backward.points[0, 0] == 50.0 and forward.length == pytest.approx(50.0)
    left = lanes_of([road], driving_side="left")
    assert left[0].points[0, 1] == pytest.approx(6.5 / 4)
    one_way = lanes_of([RoadSpec(road.centerline, width=6.5, lanes=2, oneway=True, highway="primary")])
    assert len(one_way) == 2 and all(lane.forward for lane in one_way)
    assert sorted(lane.points[0, 1] for lane in one_way) == pytest.approx([-6.5 / 4, 6.5 / 4])
    assert one_way[0].speed == SPEED_BY_HIGHWAY["primary"]
    with pytest.raises(ValueError, match="driving_side"):
        lanes_of([road], driving_side="middle")


def test_cars_keep_to_their_lanes_their_speed_and_their_distance() -> None:
    lanes = lanes_of(_block())
    traffic = Traffic(lanes, np.zeros((0, 2)), cars=10, seed=0)
    states = _run(traffic, 120.0)
    for state in states:
        assert (state.speeds <= SPEED_BY_HIGHWAY["residential"] + 1e-6).all()
        for lane in set(state.lanes.tolist()):
            ss = sorted(lanes[lane].project(p)[0] for p in state.positions[state.lanes == lane])
            assert all(b - a >= CAR_LENGTH + 0.5 for a, b in itertools.pairwise(ss))
        for car, lane in enumerate(state.lanes):
            assert lanes[lane].project(state.positions[car])[1] < 1e-6
    travelled = np.array([s.speeds for s in states]).sum(axis=0) * 0.1
    assert (travelled > 300.0).all()  # round the block and on: every car keeps moving


def test_the_same_seed_gives_the_same_traffic() -> None:
    def run(seed: int) -> bytes:
        traffic = Traffic(lanes_of(_block()), np.zeros((0, 2)), cars=8, seed=seed)
        return b"".join(s.positions.tobytes() for s in _run(traffic, 30.0))

    assert run(3) == run(3) and run(3) != run(4)


def test_cars_stop_for_a_person_on_a_crossing_and_go_on_when_it_is_clear() -> None:
    road = RoadSpec(np.array([(0.0, 0.0), (200.0, 0.0)]), width=6.5)
    crossing = np.array([[120.0, 0.0]])
    lanes = lanes_of([road])
    traffic = Traffic(lanes[:1], crossing, cars=1, seed=0)  # the eastbound lane only
    start = traffic.state().positions[0, 0]
    assert start < 120.0 - STOP_BEFORE  # the seed puts it before the crossing
    person = np.array([[120.0, 1.0]])  # on the crossing, in the car's lane
    states = _run(traffic, 40.0, people=person)
    xs = np.array([s.positions[0, 0] for s in states])
    assert xs.max() < 120.0 - STOP_BEFORE + 0.3  # it halted before the crossing
    assert states[-1].speeds[0] < 0.05 and states[-1].stopped_for_people[0]
    states = _run(traffic, 20.0, people=np.array([[120.0, 8.0]]))  # the person is on the sidewalk
    assert any(s.positions[0, 0] > 125.0 for s in states) and not states[-1].stopped_for_people[0]


def test_a_person_beside_the_road_or_away_from_the_crossing_holds_no_car() -> None:
    road = RoadSpec(np.array([(0.0, 0.0), (200.0, 0.0)]), width=6.5)
    lanes = lanes_of([road])
    for where in ([120.0, 6.0], [140.0, 0.5]):  # on the sidewalk by the crossing; on the road 20 m on
        traffic = Traffic(lanes[:1], np.array([[120.0, 0.0]]), cars=1, seed=0)
        states = _run(traffic, 30.0, people=np.array([where]))
        assert not any(s.stopped_for_people[0] for s in states)


def test_a_bad_step_is_refused() -> None:
    traffic = Traffic(lanes_of(_block()), np.zeros((0, 2)), cars=2, seed=0)
    with pytest.raises(ValueError, match="positive time"):
        traffic.step(0.0)
