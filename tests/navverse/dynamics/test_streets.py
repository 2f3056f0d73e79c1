"""The street plan of a scene: crossings from the navmesh's crosswalk polygons, roads from its look."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from navverse.dynamics.streets import crossings_of, scene_streets
from navverse.look.files import write_look
from navverse.look.scene_look import MapDetails, MarkedRoad
from navverse.look.settings import EVAL_LOOK
from tests.navverse.dynamics.test_crowd import _street


def test_each_crosswalk_is_one_crossing_at_its_centre() -> None:
    crossings = crossings_of(_street())
    assert crossings.shape == (1, 2)
    np.testing.assert_allclose(crossings[0], (0.0, 0.0), atol=0.3)


def test_a_navmesh_without_crosswalks_has_no_crossings() -> None:
    finder = _street()
    finder.name_areas({"sidewalk": 7, "road": 6})
    assert crossings_of(finder).shape == (0, 2)


def test_the_roads_are_those_the_look_keeps(tmp_path: Path) -> None:
    scene_dir = tmp_path / "scene"
    scene_dir.mkdir()
    finder = _street()
    assert scene_streets(scene_dir, finder).roads == []  # no look: no roads
    road = MarkedRoad(((-20.0, 0.0), (20.0, 0.0)), 12.0, 4, False, "secondary")
    details = MapDetails(buildings={}, roads=[road], crossings=[(0.0, 0.0, "zebra")])
    write_look(scene_dir / "look.json", EVAL_LOOK, details, geometry_sha256="0" * 64)
    plan = scene_streets(scene_dir, finder)
    assert len(plan.roads) == 1 and plan.roads[0].lanes == 4 and plan.roads[0].highway == "secondary"
    np.testing.assert_allclose(plan.roads[0].centerline, [(-20.0, 0.0), (20.0, 0.0)])
    assert plan.crossings.shape == (1, 2)
