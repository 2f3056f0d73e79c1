"""Spot follows navmesh paths of a furnished procedural apartment with the waypoint interface."""

from __future__ import annotations

import numpy as np
import pytest

from navverse import nav
from navverse.indoor import generate_building
from navverse.nav.sampling import sample_paths
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.sim.embodiments import make_embodiment
from navverse.sim.rollout import follow_path
from navverse.sim.simulator import Simulator
from navverse.sim.world import World

PATHS = 12


@pytest.mark.parametrize("seed", [0])
def test_spot_ends_every_path_within_the_success_tolerance(
    seed: int, tmp_path_factory: pytest.TempPathFactory
):
    scene = generate_building("apartment", np.random.default_rng(seed), scene_id=f"apartment-{seed}")
    finder = build_scene_navmesh(scene, nav.INDOOR)
    paths = sample_paths(finder, seed, PATHS, min_length=5.0, max_length=50.0)
    robot = make_embodiment("spot")
    tolerance = 1.0 + robot.radius  # the paper's success radius, 1.6 m for Spot
    with World(scene, collision_cache=tmp_path_factory.mktemp("coacd")) as world:
        sim = Simulator(world, robot)
        outcomes = []
        for path in paths:
            heading = path.points[1, :2] - path.points[0, :2]
            sim.spawn(path.points[0], float(np.arctan2(heading[1], heading[0])))
            outcomes.append(follow_path(sim, path.points))
    assert all(o.final_distance <= tolerance for o in outcomes), [o.final_distance for o in outcomes]
    assert all(o.termination is None for o in outcomes)
    # It really drove the paths: the executed length is the path's (corners are cut by the lookahead).
    for path, outcome in zip(paths, outcomes, strict=True):
        assert outcome.traveled == pytest.approx(path.geodesic_distance, rel=0.1)
        assert outcome.duration > path.geodesic_distance / 1.5  # never faster than the speed limit
