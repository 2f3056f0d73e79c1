"""Spot follows navmesh paths across a synthetic city under full physics: curbs, crosswalks, ramps.

(`scripts/path_following.py --scene <city>` runs the same over 100 paths of a built city.)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from navverse.city.geometry.scene import CityGeometry, city_scene
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city
from navverse.nav import OUTDOOR
from navverse.nav.sampling import sample_paths
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.sim.embodiments import make_embodiment
from navverse.sim.rollout import follow_path
from navverse.sim.simulator import Simulator
from navverse.sim.world import World

PATHS = 6


def test_spot_ends_city_paths_within_the_success_tolerance(tmp_path: Path) -> None:
    city = synthetic_city(SyntheticCityParams(size=(200.0, 200.0)), seed=5)
    scene = city_scene(city, scene_id="city", geometry=CityGeometry())
    finder = build_scene_navmesh(scene, OUTDOOR, area_costs={"road": 3.0, "curb": 3.0, "ground": 2.0})
    paths = sample_paths(finder, 11, PATHS, min_length=20.0, max_length=50.0)
    levels = np.concatenate([p.points[:, 2] for p in paths])
    assert levels.min() < -0.15 < -0.05 < levels.max()  # the paths really go down to the roads and up
    robot = make_embodiment("spot")
    with World(scene, collision_cache=tmp_path) as world:
        sim = Simulator(world, robot)
        outcomes = []
        for path in paths:
            heading = path.points[1, :2] - path.points[0, :2]
            sim.spawn(path.points[0], float(np.arctan2(heading[1], heading[0])))
            outcomes.append(follow_path(sim, path.points))
    assert all(o.termination is None for o in outcomes), [o.termination for o in outcomes]
    assert all(o.final_distance <= 1.0 + robot.radius for o in outcomes), [o.final_distance for o in outcomes]
    for path, outcome in zip(paths, outcomes, strict=True):
        assert outcome.traveled == pytest.approx(path.geodesic_distance, rel=0.15)
