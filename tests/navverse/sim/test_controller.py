"""The waypoint follower on an ideal (kinematic) robot: lookahead, reach tolerances, limits, streaming."""

from __future__ import annotations

import math

import pytest

from navverse.sim.actions import discrete_waypoint
from navverse.sim.controller import (
    LIMITS,
    LOOKAHEAD,
    PID,
    REACH_DISTANCE,
    Waypoint,
    WaypointFollower,
    wrap_angle,
)

DT = 0.02


def integrate(follower: WaypointFollower, pose: tuple[float, float, float], *, seconds: float):
    """Drive a robot that executes the commanded body velocity exactly; return the end pose and commands."""
    x, y, yaw = pose
    commands = []
    for _ in range(round(seconds / DT)):
        vx, vy, wz = follower.command(x, y, yaw, dt=DT)
        commands.append((vx, vy, wz))
        x += (vx * math.cos(yaw) - vy * math.sin(yaw)) * DT
        y += (vx * math.sin(yaw) + vy * math.cos(yaw)) * DT
        yaw = wrap_angle(yaw + wz * DT)
        if follower.done:
            break
    return (x, y, yaw), commands


def test_an_l_shaped_path_is_followed_to_its_end_and_heading():
    follower = WaypointFollower()
    path = [Waypoint(4.0, 0.0), Waypoint(4.0, 3.0, math.pi / 2)]
    follower.set_path(path, start=(0.0, 0.0))
    (x, y, yaw), commands = integrate(follower, (0.0, 0.0, 0.0), seconds=30.0)
    assert follower.done
    assert math.hypot(x - 4.0, y - 3.0) < REACH_DISTANCE
    assert abs(wrap_angle(yaw - math.pi / 2)) < math.radians(3)
    # Commands always respect the paper's clip.
    assert max(abs(c[0]) for c in commands) <= LIMITS[0] + 1e-9
    assert max(abs(c[1]) for c in commands) <= LIMITS[1] + 1e-9
    assert max(abs(c[2]) for c in commands) <= LIMITS[2] + 1e-9
    # It cruises at the speed limit on the long straight.
    assert max(c[0] for c in commands) == pytest.approx(LIMITS[0], abs=1e-6)


def test_the_embodiments_own_limits_clip_tighter():
    follower = WaypointFollower(limits=(0.7, 0.0, 1.0))
    assert follower.clip == (0.7, 0.0, 1.0) and not follower.holonomic
    follower.set_path([Waypoint(3.0, 2.0)], start=(0.0, 0.0))
    (x, y, _), commands = integrate(follower, (0.0, 0.0, 0.0), seconds=30.0)
    assert follower.done and math.hypot(x - 3.0, y - 2.0) < REACH_DISTANCE
    assert all(c[1] == 0.0 for c in commands)  # a differential drive never side-steps
    assert max(abs(c[0]) for c in commands) <= 0.7 + 1e-9
    assert max(abs(c[2]) for c in commands) <= 1.0 + 1e-9


def test_the_lookahead_point_is_lookahead_along_the_path():
    follower = WaypointFollower()
    follower.set_path([Waypoint(0.1, 0.0), Waypoint(0.1, 5.0)], start=(0.0, 0.0))
    tx, ty, final = follower._lookahead_point(0.0, 0.0)
    # 0.1 m to the corner, the rest of the lookahead along the second segment.
    assert (tx, ty, final) == pytest.approx((0.1, LOOKAHEAD - 0.1, False))


def test_the_goal_needs_the_yaw_as_well_as_the_position():
    follower = WaypointFollower()
    follower.set_path([Waypoint(1.0, 0.0, math.pi)], start=(0.0, 0.0))
    assert not follower.reached(1.0, 0.0, 0.0)  # right place, wrong heading
    assert not follower.reached(1.0 + 2 * REACH_DISTANCE, 0.0, math.pi)  # right heading, too far
    assert follower.reached(1.0 + REACH_DISTANCE / 2, 0.0, math.pi - math.radians(2))


def test_streamed_waypoints_extend_the_path_without_stopping():
    follower = WaypointFollower()
    follower.set_path([Waypoint(2.0, 0.0)], start=(0.0, 0.0))
    pose, _ = integrate(follower, (0.0, 0.0, 0.0), seconds=1.0)
    assert not follower.done
    follower.extend([Waypoint(4.0, 0.0)])
    pose, second = integrate(follower, pose, seconds=20.0)
    assert follower.done and math.hypot(pose[0] - 4.0, pose[1]) < REACH_DISTANCE
    # Passing x = 2 while streaming, the robot did not brake to a stop there.
    speeds_near_two = [c[0] for c in second[:40]]
    assert min(speeds_near_two) > 0.5


def test_pid_integral_is_clamped():
    pid = PID(kp=0.0, ki=1.0, integral_limit=0.5)
    for _ in range(100):
        out = pid(1.0, 0.1)
    assert out == pytest.approx(0.5)
    pid.reset()
    assert pid(0.0, 0.1) == 0.0


@pytest.mark.parametrize(
    ("action", "expected"),
    [
        ("forward", (1.0, 1.25, math.pi / 2)),
        ("left", (0.75, 1.0, math.pi / 2)),
        ("right", (1.25, 1.0, math.pi / 2)),
        ("rotate_left", (1.0, 1.0, math.pi / 2 + math.radians(30))),
        ("small_rotate_right", (1.0, 1.0, math.pi / 2 - math.radians(15))),
    ],
)
def test_discrete_actions_map_to_the_papers_table(action, expected):
    wp = discrete_waypoint(action, 1.0, 1.0, math.pi / 2, step=0.25)
    assert (wp.x, wp.y, wp.yaw) == pytest.approx(expected)
    assert discrete_waypoint("stop", 1.0, 1.0, 0.0, step=0.25) is None
    with pytest.raises(ValueError, match="unknown discrete action"):
        discrete_waypoint("jump", 0.0, 0.0, 0.0, step=0.25)
