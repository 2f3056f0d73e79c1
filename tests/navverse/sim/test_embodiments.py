"""The robots, really simulated on purpose-built geometry: curbs, a ledge, a wall, friction, determinism."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import pytest

from navverse.errors import NavverseError
from navverse.scene.geometry import MeshData, Surface
from navverse.sim.embodiment import FALL_TILT, Embodiment, tilt
from navverse.sim.embodiments import EMBODIMENTS, UnknownEmbodimentError, make_embodiment
from navverse.sim.turtlebot import AXLE_X
from navverse.sim.world import CONTROL_HZ, GRAVITY, PHYSICS_HZ, World
from tests.scenes import scene_of

SUBSTEPS = PHYSICS_HZ // CONTROL_HZ
CURB = 0.2
LEDGE = 1.0
EDGE_X = 4.0  # where the curb, the ledge or the low-friction run starts


def _slab(x0: float, x1: float, top: float, *, width: float = 8.0, bottom: float = -1.5) -> MeshData:
    """A box from x0 to x1 (centred on y = 0) whose top face is at `top`."""
    return MeshData.box((x1 - x0, width, top - bottom), center=((x0 + x1) / 2, 0.0, (top + bottom) / 2))


def _world(surfaces: list[tuple[str, str, MeshData]], *, friction: dict[str, float] | None = None) -> World:
    scene = scene_of(
        [Surface(name, tc, mesh) for name, tc, mesh in surfaces],
        scene_id="embodiment_test",
        scene_type="outdoor",
        friction=friction,
    )
    return World(scene, collision_cache=None)


def _curb_surfaces() -> list[tuple[str, str, MeshData]]:
    return [("floor", "floor", _slab(-5.0, EDGE_X, 0.0)), ("sidewalk", "sidewalk", _slab(EDGE_X, 16.0, CURB))]


@pytest.fixture
def curb_world() -> Iterator[World]:
    """Floor at z = 0 up to x = 4, then a sidewalk 0.2 m higher (the curb's face at x = 4)."""
    with _world(_curb_surfaces()) as w:
        yield w


@pytest.fixture
def wall_world() -> Iterator[World]:
    """Floor at z = 0 with a 2 m high wall whose face is at x = 3."""
    wall = MeshData.box((0.2, 6.0, 2.0), center=(3.1, 0.0, 1.0))
    with _world([("floor", "floor", _slab(-5.0, 16.0, 0.0)), ("wall", "wall", wall)]) as w:
        yield w


def _tick(world: World, robot: Embodiment, periods: int = 1) -> None:
    for _ in range(periods):
        for _ in range(SUBSTEPS):
            robot.before_step()
            world.step()


def _yaw(quaternion: np.ndarray) -> float:
    x, y, z, w = quaternion
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def _spawned(name: str, world: World, position: tuple[float, float, float], yaw: float = 0.0) -> Embodiment:
    robot = make_embodiment(name)
    robot.spawn(world, position, yaw)
    return robot


# ---------------------------------------------------------------------------------------------- spot


def test_spot_steps_up_a_curb_and_back_down(curb_world: World) -> None:
    robot = _spawned("spot", curb_world, (1.5, 0.0, 0.0))
    stand = robot.standing_height  # type: ignore[attr-defined]
    max_tilt = 0.0
    robot.set_command(1.5, 0.0, 0.0)
    while robot.base_pose()[0][0] < 7.0 and curb_world.time < 10.0:
        _tick(curb_world, robot)
        max_tilt = max(max_tilt, tilt(robot.base_pose()[1]))
    robot.set_command(0.0, 0.0, 0.0)
    _tick(curb_world, robot, 50)
    upper = robot.base_pose()[0][2] - stand
    # Turn round on the sidewalk (yaw feedback, as a controller would), then walk back down.
    while (
        abs(error := math.remainder(math.pi - _yaw(robot.base_pose()[1]), math.tau)) > 0.02
        and curb_world.time < 20
    ):
        robot.set_command(0.0, 0.0, 2.0 * error)
        _tick(curb_world, robot)
        max_tilt = max(max_tilt, tilt(robot.base_pose()[1]))
    robot.set_command(1.5, 0.0, 0.0)
    while robot.base_pose()[0][0] > 1.0 and curb_world.time < 30.0:
        _tick(curb_world, robot)
        max_tilt = max(max_tilt, tilt(robot.base_pose()[1]))
    robot.set_command(0.0, 0.0, 0.0)
    _tick(curb_world, robot, 50)
    position, quaternion = robot.base_pose()
    print(
        f"spot curb: level reached {upper:.3f} m, back at {position[2] - stand:.3f} m, "
        f"max tilt {math.degrees(max_tilt):.1f} deg, x {position[0]:.2f} m at t={curb_world.time:.2f} s"
    )
    assert upper == pytest.approx(CURB, abs=0.01)  # standing on the sidewalk
    assert position[0] <= 1.0 and position[2] - stand == pytest.approx(0.0, abs=0.01)  # back on the floor
    assert max_tilt < FALL_TILT
    assert math.degrees(max_tilt) < 10.0  # the stance keeps the trunk nearly level over the step
    assert tilt(quaternion) < math.radians(1.0)


@pytest.mark.parametrize(("height", "climbed"), [(0.3, True), (0.4, False)])
def test_spot_climbs_curbs_up_to_its_step_height(height: float, climbed: bool) -> None:
    surfaces = [
        ("floor", "floor", _slab(-5.0, EDGE_X, 0.0)),
        ("sidewalk", "sidewalk", _slab(EDGE_X, 16.0, height)),
    ]
    with _world(surfaces) as world:
        robot = _spawned("spot", world, (1.5, 0.0, 0.0))
        robot.set_command(1.0, 0.0, 0.0)
        collided = max_tilt = 0.0
        for _ in range(300):
            _tick(world, robot)
            max_tilt = max(max_tilt, tilt(robot.base_pose()[1]))
            collided += any(c.body.terrain_class == "sidewalk" for c in world.contacts(robot.body))
        position = robot.base_pose()[0]
        assert max_tilt < FALL_TILT  # it never falls: it climbs, or it is stopped
        if climbed:
            assert position[0] > 6.0 and position[2] == pytest.approx(
                height + robot.standing_height, abs=0.01
            )
            assert collided == 0
        else:  # the legs (the box between the hips) hit the curb's face: stopped below it
            assert position[0] < EDGE_X and collided > 100


def test_spot_walking_over_a_ledge_falls() -> None:
    surfaces = [("upper", "floor", _slab(-5.0, EDGE_X, LEDGE)), ("lower", "ground", _slab(EDGE_X, 16.0, 0.0))]
    with _world(surfaces) as world:
        robot = _spawned("spot", world, (2.0, 0.0, LEDGE))
        robot.set_command(1.0, 0.0, 0.0)
        tilts, heights = [], []
        for _ in range(150):
            _tick(world, robot)
            position, quaternion = robot.base_pose()
            tilts.append(tilt(quaternion))
            heights.append(position[2])
        first = next(i for i, t in enumerate(tilts) if t > FALL_TILT)
        print(
            f"spot ledge: tilt > 45 deg at t={first / CONTROL_HZ:.2f} s after start, "
            f"max tilt {math.degrees(max(tilts)):.0f} deg, final height {heights[-1]:.2f} m"
        )
        assert max(tilts) > FALL_TILT
        assert heights[-1] < LEDGE  # it ended on the lower level
        assert min(heights[:first]) > LEDGE  # it was walking on the upper level until it tipped


# ---------------------------------------------------------------------------------------------- turtlebot


def test_turtlebot_is_stopped_by_a_curb(curb_world: World) -> None:
    robot = _spawned("turtlebot", curb_world, (2.0, 0.0, 0.0))
    robot.set_command(0.7, 0.0, 0.0)
    _tick(curb_world, robot, 250)  # 5 s: it would be 1.5 m past the curb
    position, quaternion = robot.base_pose()
    front = position[0] - AXLE_X + robot.size[0] / 2  # the base origin is mid-axle, AXLE_X from the centre
    print(f"turtlebot curb: front at x={front:.3f} m (curb face at {EDGE_X}), base z {position[2]:.3f} m")
    assert front == pytest.approx(EDGE_X, abs=0.01)
    assert position[2] == pytest.approx(robot.standing_height, abs=0.005)  # type: ignore[attr-defined]
    assert tilt(quaternion) < math.radians(3.0)
    hits = [c for c in curb_world.contacts(robot.body) if c.body.terrain_class == "sidewalk"]
    assert hits and not any(robot.is_ground_contact(c) for c in hits)


def _start_stop_run(friction: float, *, legs: int = 5, leg: float = 2.0) -> tuple[float, float, float]:
    """10 m in 2 m legs, full speed then a stop at each waypoint, as the controller drives a path.

    Returns the time taken, the mean braking distance (from the stop command to standstill) and the
    mean time from the start command to 95% of full speed.
    """
    with _world([("run", "road", _slab(-2.0, 16.0, 0.0))], friction={"road": friction}) as world:
        robot = _spawned("turtlebot", world, (0.0, 0.0, 0.0))
        full = robot.max_velocity[0]
        braking, rising = [], []
        for k in range(1, legs + 1):
            start = world.time
            robot.set_command(full, 0.0, 0.0)
            reached = None
            while robot.base_pose()[0][0] < k * leg:
                _tick(world, robot)
                if reached is None and robot.base_velocity()[0][0] >= 0.95 * full:
                    reached = world.time - start
            rising.append(reached)
            stop_x = robot.base_pose()[0][0]
            robot.set_command(0.0, 0.0, 0.0)
            while robot.base_velocity()[0][0] > 0.005:
                _tick(world, robot)
            braking.append(robot.base_pose()[0][0] - stop_x)
        return world.time, float(np.mean(braking)), float(np.mean(rising))


def test_turtlebot_is_slower_on_low_friction() -> None:
    slow = _start_stop_run(0.5)
    fast = _start_stop_run(1.0)
    print(
        f"turtlebot 10 m start-stop run: mu=0.5 {slow[0]:.2f} s, braking {slow[1] * 100:.1f} cm, "
        f"to 95% speed {slow[2]:.2f} s; mu=1.0 {fast[0]:.2f} s, braking {fast[1] * 100:.1f} cm, "
        f"to 95% speed {fast[2]:.2f} s"
    )
    # Friction bounds the deceleration by mu g: no stop is shorter than v^2 / (2 mu g), 5.0 cm at
    # mu = 0.5 and 2.5 cm at mu = 1.0 (it is longer still: braking shifts load onto the front caster).
    full = 0.7
    assert slow[1] >= full**2 / (2 * 0.5 * GRAVITY)
    assert fast[1] >= full**2 / (2 * 1.0 * GRAVITY)
    assert slow[1] > 1.4 * fast[1]
    # Each start and stop loses about v / (2 a) + v / (2 a) more at mu = 0.5 (~0.05 s), five times.
    assert slow[2] > fast[2] + 0.04
    assert slow[0] > fast[0] + 0.2


def _ramp(length: float, slope: float, *, width: float = 4.0, thickness: float = 0.3) -> MeshData:
    """A slab rising at `slope` radians along +x from the origin, `length` m along its top face."""
    box = MeshData.box((length, width, thickness), center=(length / 2, 0.0, -thickness / 2))
    c, s = math.cos(slope), math.sin(slope)
    return MeshData(box.vertices @ np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]]).T, box.faces)


def _ramp_progress(friction: float, slope: float) -> tuple[float, float]:
    """Drive up a 10 m ramp from 1 m along it; return the distance along it after 20 s (or at 9 m) and the
    time taken."""
    surfaces = [("run", "road", _ramp(10.0, slope)), ("floor", "floor", _slab(-5.0, 0.0, 0.0))]
    with _world(surfaces, friction={"road": friction}) as world:
        robot = _spawned("turtlebot", world, (math.cos(slope), 0.0, math.sin(slope)))
        robot.set_command(robot.max_velocity[0], 0.0, 0.0)
        along = 1.0
        while along < 9.0 and world.time < 20.0:
            _tick(world, robot)
            position = robot.base_pose()[0]
            along = position[0] * math.cos(slope) + position[2] * math.sin(slope)
        return along, world.time


def test_turtlebot_climbs_a_steep_ramp_only_with_enough_friction() -> None:
    # Climbing needs mu >= tan(slope) / (share of the weight on the wheels): tan(25 deg) = 0.47, and the
    # casters carry some of the weight, so mu = 0.5 is not enough and mu = 1.0 is plenty.
    slope = math.radians(25.0)
    slips, climbs = _ramp_progress(0.5, slope), _ramp_progress(1.0, slope)
    print(
        f"turtlebot 25 deg ramp from 1 m: mu=0.5 at {slips[0]:.2f} m after {slips[1]:.1f} s; "
        f"mu=1.0 at {climbs[0]:.2f} m after {climbs[1]:.1f} s"
    )
    assert climbs[0] >= 9.0 and climbs[1] < 8.0 / 0.7 * 1.2
    assert slips[0] < 1.0  # it slid back down


# ---------------------------------------------------------------------------------------------- both


@pytest.mark.parametrize("name", sorted(EMBODIMENTS))
def test_a_wall_is_a_collision_and_the_floor_is_support(name: str, wall_world: World) -> None:
    robot = _spawned(name, wall_world, (0.0, 0.0, 0.0))
    _tick(wall_world, robot, 10)
    support = wall_world.contacts(robot.body)
    robot.set_command(robot.max_velocity[0], 0.0, 0.0)
    _tick(wall_world, robot, 300)
    contacts = wall_world.contacts(robot.body)
    walls = [c for c in contacts if c.body.terrain_class == "wall"]
    position = robot.base_pose()[0]
    print(
        f"{name} wall: front at x={position[0] + robot.size[0] / 2:.3f} (wall at 3.0), wall contacts "
        f"{len(walls)}, {sum(c.force for c in walls):.0f} N"
    )
    assert walls and not any(robot.is_ground_contact(c) for c in walls)
    assert not walls[0].body.navigable
    assert position[0] + robot.size[0] / 2 == pytest.approx(3.0, abs=0.05)  # stopped at the wall
    if name == "turtlebot":
        wheels = [c for c in support if c.link in robot.wheel_joints]  # type: ignore[attr-defined]
        assert wheels and all(robot.is_ground_contact(c) for c in support)
    else:
        # Spot stands on its legs, which are not collision geometry: standing makes no contact at all.
        assert support == []
        assert (robot.leg_forces() > 0).all()  # type: ignore[attr-defined]


@pytest.mark.parametrize("name", sorted(EMBODIMENTS))
def test_spawn_settles_without_bouncing(name: str, curb_world: World) -> None:
    robot = _spawned(name, curb_world, (6.0, 0.5, CURB), yaw=0.7)
    assert isinstance(robot, Embodiment)
    heights, tilts = [], []
    for _ in range(100):
        _tick(curb_world, robot)
        position, quaternion = robot.base_pose()
        heights.append(position[2])
        tilts.append(tilt(quaternion))
    linear, angular = robot.base_velocity()
    expected = CURB + robot.standing_height  # type: ignore[attr-defined]
    print(f"{name} settle: height {min(heights):.4f}..{max(heights):.4f} m (expected {expected:.4f})")
    assert max(heights) - min(heights) < 0.002
    assert np.mean(heights) == pytest.approx(expected, abs=0.002)
    assert max(tilts) < math.radians(0.5)
    assert np.linalg.norm(linear) < 1e-3 and np.linalg.norm(angular) < 1e-3
    assert position[:2] == pytest.approx((6.0, 0.5), abs=1e-3)
    assert _yaw(quaternion) == pytest.approx(0.7, abs=1e-3)
    # The camera looks forward (optical z along base x) at the robot's camera height.
    camera = robot.camera_to_base
    assert camera[:3, 2] == pytest.approx((1.0, 0.0, 0.0))
    assert camera[2, 3] + robot.standing_height == pytest.approx(  # type: ignore[attr-defined]
        {"spot": 0.6, "turtlebot": 0.4}[name], abs=0.01
    )


@pytest.mark.parametrize("name", sorted(EMBODIMENTS))
def test_commands_are_clipped_to_the_limits(name: str, wall_world: World) -> None:
    robot = _spawned(name, wall_world, (-4.0, 0.0, 0.0))
    robot.set_command(10.0, -10.0, float("nan"))
    assert robot.command == (robot.max_velocity[0], -robot.max_velocity[1], 0.0)  # type: ignore[attr-defined]
    robot.set_command(-10.0, 10.0, 10.0)
    assert robot.command == (-robot.max_velocity[0], robot.max_velocity[1], robot.max_velocity[2])  # type: ignore[attr-defined]
    robot.set_command(10.0, 0.0, 0.0)
    _tick(wall_world, robot, 75)
    speed = float(np.linalg.norm(robot.base_velocity()[0][:2]))
    assert speed == pytest.approx(robot.max_velocity[0], rel=0.02)
    robot.set_command(0.0, 0.0, -10.0)
    _tick(wall_world, robot, 75)
    assert robot.base_velocity()[1][2] == pytest.approx(-robot.max_velocity[2], rel=0.05)


def _trajectory(name: str) -> np.ndarray:
    with _world(_curb_surfaces()) as world:
        robot = _spawned(name, world, (1.0, 0.3, 0.0), yaw=0.1)
        rows = []
        for vx, vy, wz, periods in (
            (1.0, 0.2, 0.3, 60),
            (0.5, -0.3, -1.0, 40),
            (1.5, 0.0, 0.0, 80),
            (0, 0, 0, 20),
        ):
            robot.set_command(vx, vy, wz)
            for _ in range(periods):
                _tick(world, robot)
                rows.append(np.concatenate([*robot.base_pose(), *robot.base_velocity()]))
        return np.array(rows)


@pytest.mark.parametrize("name", sorted(EMBODIMENTS))
def test_same_commands_give_the_same_trajectory(name: str) -> None:
    first, second = _trajectory(name), _trajectory(name)
    assert np.linalg.norm(first[-1, :2] - first[0, :2]) > 1.0  # it went somewhere
    assert np.array_equal(first, second)


def test_unknown_embodiment_lists_the_known_ones() -> None:
    with pytest.raises(UnknownEmbodimentError, match=r"'unicycle'.*spot, turtlebot") as info:
        make_embodiment("unicycle")
    assert isinstance(info.value, NavverseError)


@pytest.mark.parametrize("name", sorted(EMBODIMENTS))
def test_remove_takes_the_robot_out_and_it_can_spawn_again(name: str, wall_world: World) -> None:
    bodies = wall_world.client.getNumBodies()
    robot = _spawned(name, wall_world, (0.0, 0.0, 0.0))
    assert wall_world.client.getNumBodies() == bodies + 1
    robot.remove()
    assert robot.body == -1 and wall_world.client.getNumBodies() == bodies
    robot.spawn(wall_world, (1.0, 0.0, 0.0), 0.0)
    _tick(wall_world, robot, 5)
    assert robot.base_pose()[0][0] == pytest.approx(1.0, abs=1e-3)


def test_spot_and_turtlebot_are_sized_as_specified() -> None:
    spot, turtlebot = make_embodiment("spot"), make_embodiment("turtlebot")
    assert spot.radius == 0.6 and spot.size[:2] == (1.1, 0.5) and spot.max_velocity[0] == 1.5
    assert turtlebot.radius == pytest.approx(0.2) and turtlebot.max_velocity == (0.7, 0.0, 2.8)
    assert spot.body == turtlebot.body == -1
