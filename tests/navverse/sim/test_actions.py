"""The action interfaces on flat ground: discrete primitives by the table's amounts, waypoints, velocities."""

from __future__ import annotations

import math
from collections.abc import Iterator

import pytest

from navverse.scene.geometry import MeshData, Surface
from navverse.sim.actions import DISCRETE_ACTIONS, DISCRETE_TIMEOUT, ActionRunner, step_size
from navverse.sim.controller import REACH_DISTANCE, REACH_YAW, Waypoint, wrap_angle
from navverse.sim.embodiments import make_embodiment
from navverse.sim.simulator import Simulator
from navverse.sim.world import World
from tests.scenes import scene_of

TOLERANCE = 0.02  # m
TOLERANCE_YAW = math.radians(2.0)
# Every motion primitive twice, interleaved so that each starts from a different heading.
SEQUENCE = [a for a in DISCRETE_ACTIONS if a != "stop"] * 2


@pytest.fixture(scope="module")
def flat_world() -> Iterator[World]:
    floor = Surface("floor", "floor", MeshData.box((40, 40, 1), center=(0, 0, -0.5)))
    scene = scene_of([floor], scene_id="flat")
    with World(scene, collision_cache=None) as world:
        yield world


def _pose(sim: Simulator) -> tuple[float, float, float]:
    pose = sim.pose()
    return float(pose.position[0]), float(pose.position[1]), pose.yaw


def _expected(action: str, x: float, y: float, yaw: float, step: float) -> tuple[float, float, float]:
    """The table's motion, written out independently of ``discrete_waypoint``."""
    forward = {"forward": step, "left": 0.0, "right": 0.0}.get(action, 0.0)
    left = {"left": step, "right": -step}.get(action, 0.0)
    turn = {"rotate_left": 30, "rotate_right": -30, "small_rotate_left": 15, "small_rotate_right": -15}
    return (
        x + forward * math.cos(yaw) - left * math.sin(yaw),
        y + forward * math.sin(yaw) + left * math.cos(yaw),
        yaw + math.radians(turn.get(action, 0.0)),
    )


@pytest.mark.parametrize("embodiment", ["spot", "turtlebot"])
@pytest.mark.parametrize("scene_type", ["indoor", "outdoor"])
def test_discrete_actions_move_by_the_tables_amounts(flat_world: World, embodiment: str, scene_type: str):
    sim = Simulator(flat_world, make_embodiment(embodiment))
    sim.spawn((0.0, 0.0, 0.0), 0.4)
    step = step_size(scene_type)
    runner = ActionRunner(sim, step=step)
    try:
        for action in SEQUENCE:
            before = _pose(sim)
            seconds = runner.discrete(action)
            x, y, yaw = _pose(sim)
            ex, ey, eyaw = _expected(action, *before, step)
            assert math.hypot(x - ex, y - ey) < TOLERANCE, (action, before, (x, y))
            assert abs(wrap_angle(yaw - eyaw)) < TOLERANCE_YAW, (action, math.degrees(yaw - eyaw))
            assert 0.2 < seconds < DISCRETE_TIMEOUT  # run until it settled, not cut off
    finally:
        sim.robot.remove()


def test_stop_does_not_move(flat_world: World):
    sim = Simulator(flat_world, make_embodiment("spot"))
    sim.spawn((1.0, 1.0, 0.0), 0.0)
    runner = ActionRunner(sim, step=0.25)
    before = _pose(sim)
    runner.discrete("stop")
    assert _pose(sim) == pytest.approx(before, abs=1e-3)
    sim.robot.remove()


def test_streamed_waypoints_are_followed_without_stopping(flat_world: World):
    sim = Simulator(flat_world, make_embodiment("spot"))
    sim.spawn((0.0, 0.0, 0.0), 0.0)
    runner = ActionRunner(sim, step=0.25)
    speeds = []
    try:
        # An agent deciding at 10 Hz hands over the next waypoint each time, 0.5 m ahead of the last.
        for k in range(1, 17):
            runner.waypoints([Waypoint(0.5 * k, 0.0, 0.0 if k == 16 else None)])
            speeds.append(sim.speed())
        deadline = sim.time + 20.0
        while not runner.follower.done and sim.time < deadline:
            runner.waypoints([])
        x, y, yaw = _pose(sim)
        assert math.hypot(x - 8.0, y) < REACH_DISTANCE + 0.01 and abs(yaw) < REACH_YAW + math.radians(1)
        # It kept moving between decisions instead of stopping at every waypoint.
        assert min(speeds[5:]) > 0.3
    finally:
        sim.robot.remove()


def test_velocity_commands_bypass_the_follower(flat_world: World):
    sim = Simulator(flat_world, make_embodiment("spot"))
    sim.spawn((0.0, 0.0, 0.0), 0.0)
    runner = ActionRunner(sim, step=0.25)
    try:
        runner.velocity(0.0, 0.0, 1.0, duration=1.0)  # turn on the spot at 1 rad/s...
        _, angular = sim.robot.base_velocity()
        assert angular[2] == pytest.approx(1.0, abs=0.1)
        runner.velocity(0.0, 0.3, 0.0, duration=1.0)  # ...then step sideways (the body's left)
        linear, _ = sim.robot.base_velocity()
        yaw = sim.pose().yaw
        assert -math.sin(yaw) * linear[0] + math.cos(yaw) * linear[1] == pytest.approx(0.3, abs=0.05)
    finally:
        sim.robot.remove()
