"""Route stretches along a road: a walk down the sidewalk beside a road follows it, a walk across the
plaza behind does not, and the route text tells the street as its landmark."""

from __future__ import annotations

import numpy as np
import pytest

from navverse.episodes.instructions.directives import plan_directives
from navverse.episodes.instructions.roads import RoadFollowing
from navverse.episodes.instructions.wording import landmark_text
from navverse.scene.geometry import Surface
from tests.scenes import quad, scene_of


@pytest.fixture(scope="module")
def street():
    """A road along x (y in 0..7), a sidewalk beside it (y in 7..10) and a plaza behind (y in 10..40)."""
    return scene_of(
        [
            Surface("road", "road", quad(0.0, 0.0, 60.0, 7.0, -0.2)),
            Surface("sidewalk", "sidewalk", quad(0.0, 7.0, 60.0, 10.0, 0.0)),
            Surface("plaza", "plaza", quad(0.0, 10.0, 60.0, 40.0, 0.0)),
        ],
        scene_id="street",
        scene_type="outdoor",
    )


def test_terrain_classes_under_points(street) -> None:
    roads = RoadFollowing(street)
    assert list(roads.classes(np.array([[5.0, 3.0], [5.0, 8.5], [5.0, 20.0], [-5.0, 5.0]]))) == [
        "road",
        "sidewalk",
        "plaza",
        "",
    ]


def test_a_walk_down_the_sidewalk_follows_the_road_and_one_across_the_plaza_does_not(street) -> None:
    roads = RoadFollowing(street)
    # east along the sidewalk for 30 m, then north across the plaza for 25 m
    path = [(5.0, 8.5, 0.0), (35.0, 8.5, 0.0), (35.0, 33.5, 0.0)]
    directives = plan_directives(path, 0.0)
    assert [d.kind for d in directives] == ["start", "turn", "arrive"]
    assert roads.along_road(directives) == [True, False, False]
    # the same walk one street block inland is not along a road
    inland = plan_directives([(5.0, 25.0, 0.0), (35.0, 25.0, 0.0), (35.0, 38.0, 0.0)], 0.0)
    assert roads.along_road(inland) == [False, False, False]


def test_the_route_text_tells_the_street(street) -> None:
    directives = plan_directives([(5.0, 8.5, 0.0), (35.0, 8.5, 0.0), (35.0, 33.5, 0.0)], 0.0)
    along = RoadFollowing(street).along_road(directives)
    texts = {
        landmark_text(
            directives, [None] * len(directives), "bank", goal_seen=True, rng=np.random.default_rng(seed),
            along_road=along,
        )
        for seed in range(6)
    }  # fmt: skip
    assert all(("street" in t or "road" in t) and "bank" in t for t in texts)
    plain = landmark_text(
        directives, [None] * len(directives), "bank", goal_seen=True, rng=np.random.default_rng(0)
    )
    assert "street" not in plain and "road" not in plain


def test_an_indoor_scene_has_no_road_to_follow() -> None:
    room = scene_of([Surface("floor", "floor", quad(0.0, 0.0, 40.0, 40.0, 0.0))], scene_id="hall")
    directives = plan_directives([(2.0, 2.0, 0.0), (32.0, 2.0, 0.0), (32.0, 30.0, 0.0)], 0.0)
    assert RoadFollowing(room).along_road(directives) == [False, False, False]
