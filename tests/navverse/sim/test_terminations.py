"""Termination labels under physics (fall, out of bounds, stuck, timeout) and path rollouts."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from navverse.scene.geometry import MeshData, Surface
from navverse.sim.bullet import pybullet
from navverse.sim.embodiments import make_embodiment
from navverse.sim.rollout import follow_path
from navverse.sim.simulator import Simulator
from navverse.sim.terminations import STUCK_WINDOW, TerminationMonitor
from navverse.sim.world import World
from tests.scenes import scene_of


@pytest.fixture(scope="module")
def world() -> Iterator[World]:
    """Floor x 0..10, y -2..10 (top at z = 0), then a 1.5 m drop onto a lower floor to x = 14; a wall at
    x = 5 for y in [4, 8]: the scene's bounds are x 0..14, y -2..10, z -1.6..2. Beyond them, in the
    physics world only, the floor runs on 6 m past y = -2 (a runway that is not part of the scene)."""
    surfaces = (
        Surface("floor", "floor", MeshData.box((10.0, 12.0, 1.0), center=(5.0, 4.0, -0.5))),
        Surface("lower", "floor", MeshData.box((4.0, 12.0, 0.1), center=(12.0, 4.0, -1.55))),
        Surface("wall", "wall", MeshData.box((0.3, 4.0, 2.0), center=(5.15, 6.0, 1.0))),
    )
    scene = scene_of(surfaces, scene_id="terminations", scene_type="outdoor")
    with World(scene, collision_cache=None) as w:
        c = w.client
        runway = c.createCollisionShape(pybullet.GEOM_BOX, halfExtents=[5.0, 3.0, 0.5])
        body = c.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=runway, basePosition=[5.0, -5.0, -0.5])
        c.changeDynamics(body, -1, lateralFriction=scene.annotations.terrain_classes["floor"].friction)
        yield w


def run(sim: Simulator, monitor: TerminationMonitor, command: tuple[float, float, float], seconds: float):
    monitor.start(sim)
    for _ in range(round(seconds * 50)):
        sim.tick(*command)
        label = monitor.check(sim)
        if label is not None:
            return label, monitor.elapsed(sim)
    return None, monitor.elapsed(sim)


def test_walking_off_the_drop_is_a_fall(world: World):
    sim = Simulator(world, make_embodiment("spot"))
    sim.spawn((7.0, 1.0, 0.0), 0.0)
    label, elapsed = run(sim, TerminationMonitor(), (1.0, 0.0, 0.0), 10.0)
    assert label == "fall" and 2.5 < elapsed < 6.0  # 3 m to the edge at 1 m/s, then it tips over
    sim.robot.remove()


def test_leaving_the_bounds_is_out_of_bounds(world: World):
    sim = Simulator(world, make_embodiment("spot"))
    sim.spawn((8.0, 1.0, 0.0), -np.pi / 2)  # towards y = -2 - 2 m margin, on the floor all the way
    label, _ = run(sim, TerminationMonitor(), (1.5, 0.0, 0.0), 10.0)
    assert label == "out_of_bounds" and sim.pose().position[1] < -3.9
    sim.robot.remove()


@pytest.mark.parametrize("embodiment", ["spot", "turtlebot"])
def test_pushing_against_a_wall_is_stuck_only_when_detected(world: World, embodiment: str):
    sim = Simulator(world, make_embodiment(embodiment))
    sim.spawn((3.5, 6.0, 0.0), 0.0)
    label, elapsed = run(sim, TerminationMonitor(detect_stuck=True), (0.5, 0.0, 0.0), 20.0)
    assert label == "stuck" and STUCK_WINDOW < elapsed < STUCK_WINDOW + 5.0
    assert sim.collisions and all(c.body.terrain_class == "wall" for c in sim.collisions)
    sim.spawn((3.5, 6.0, 0.0), 0.0)
    label, _ = run(sim, TerminationMonitor(timeout=12.0), (0.5, 0.0, 0.0), 20.0)
    assert label == "timeout"  # agents are not stopped for being stuck; their time runs out
    sim.robot.remove()


def test_standing_still_is_not_stuck(world: World):
    sim = Simulator(world, make_embodiment("spot"))
    sim.spawn((2.0, 1.0, 0.0), 0.0)
    label, _ = run(sim, TerminationMonitor(detect_stuck=True, timeout=15.0), (0.0, 0.0, 0.0), 20.0)
    assert label == "timeout"
    sim.robot.remove()


def test_follow_path_goes_around_the_wall(world: World):
    sim = Simulator(world, make_embodiment("spot"))
    sim.spawn((2.0, 6.0, 0.0), 0.0)
    corners = np.array([[2.0, 6.0, 0.0], [4.0, 3.0, 0.0], [6.5, 3.0, 0.0], [8.0, 6.0, 0.0]])
    rollout = follow_path(sim, corners)
    assert rollout.arrived and rollout.termination is None and rollout.collisions == 0
    assert rollout.final_distance < 0.03
    assert rollout.traveled == pytest.approx(3.606 + 2.5 + 3.354, rel=0.05)  # the polyline's length
    assert rollout.trajectory.shape[1] == 8 and np.all(np.diff(rollout.trajectory[:, 0]) > 0)
    # Straight into the wall instead: it pushes, makes no progress and is stopped as stuck.
    sim.spawn((2.0, 6.0, 0.0), 0.0)
    blocked = follow_path(sim, np.array([[2.0, 6.0, 0.0], [8.0, 6.0, 0.0]]))
    assert not blocked.arrived and blocked.termination == "stuck" and blocked.collisions > 0
    assert blocked.final_distance > 2.5
    sim.robot.remove()
