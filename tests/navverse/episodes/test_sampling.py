"""Candidates on the navmesh (Appendix D.1): goal categories, goal regions, path lengths, start yaw."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from navverse.dataset import goal_distance
from navverse.episodes.sampling import SamplingSettings, goal_regions, object_goals, sample_scene_episodes
from navverse.nav.scene_navmesh import load_scene_navmesh
from navverse.scene.geometry import Scene
from navverse.scene.categories import CategoryRule

CATEGORIES = ["bed", "sofa", "toilet", "fridge", "chair", "armchair", "sink", "desk"]


def _draw(finder, annotations, goals, *, count: int, seed: int, settings: SamplingSettings | None = None):
    """Objnav candidates for a Spot-sized robot (r_robot 0.6 m: success within 1.6 m of the base)."""
    return sample_scene_episodes(
        finder, annotations, goals, task="objnav", count=count, rng=np.random.default_rng(seed),
        robot_radius=0.6, base_height=0.55, settings=settings,
    )  # fmt: skip


@pytest.fixture(scope="module")
def sample(apartment: Scene, scene_dirs: dict[str, Path]):
    finder = load_scene_navmesh(scene_dirs["apartment-s0"])
    goals = object_goals(apartment.annotations, categories=CATEGORIES)
    return (
        finder,
        goals,
        _draw(finder, apartment.annotations, goals, count=25, seed=4),
    )


def test_goal_rules_and_categories_choose_the_goals(apartment: Scene):
    rules = [
        CategoryRule(pattern=r"^armchair", category="sofa"),
        CategoryRule(pattern=r"^sink", category=None),
    ]
    goals = object_goals(apartment.annotations, rules=rules, categories=["sofa", "sink", "bed"])
    assert set(goals) <= {"sofa", "bed"}  # sinks dropped by the rule, the rest not listed
    objects = {o.id: o for o in apartment.annotations.objects}
    assert {objects[g.object_id].category for g in goals["sofa"]} == {"sofa", "armchair"}
    for goal in goals["bed"]:
        obj = objects[goal.object_id]
        assert goal.position == pytest.approx(obj.center, abs=1e-4)
        assert goal.radius == pytest.approx(obj.goal_radius, abs=1e-4)


def test_goal_regions_are_navigable_points_within_the_success_distance(sample):
    finder, goals, _ = sample
    for region in goal_regions(finder, goals["bed"], success=1.6):
        assert len(region.points) > 5
        assert all(goal_distance(p + (0, 0, 0.55), region.goal) <= 1.6 for p in region.points)  # the base
        assert finder.is_navigable(region.points).all()


def test_episodes_keep_the_papers_rules(sample):
    finder, _, drawn = sample
    episodes = drawn.episodes
    assert len(episodes) == 25 and len({e.episode_id for e in episodes}) == 25
    assert {e.object_category for e in episodes} <= set(CATEGORIES)
    assert len({e.object_category for e in episodes}) >= 4  # categories drawn uniformly, not one
    for e in episodes:
        assert 5.0 <= e.info.geodesic_distance <= 50.0
        path = np.asarray(e.reference_path)
        assert path[0] == pytest.approx(e.start_position, abs=1e-3)
        closest = next(g for g in e.goals if g.object_id == e.info.closest_goal_object_id)
        assert goal_distance(path[-1] + (0, 0, 0.55), closest) <= e.info.success_distance  # in its region
        # Every goal instance kept is 5-50 m away; the reference path goes to the nearest one.
        for goal in e.goals:
            (region,) = goal_regions(finder, [goal], success=e.info.success_distance)
            length = finder.find_path_multi(e.start_position, region.points).geodesic_distance
            assert 5.0 - 1e-3 <= length <= 50.0 + 1e-3
            assert length >= e.info.geodesic_distance - 1e-3
        # The start faces the next corner, within the 30 degree perturbation.
        heading = math.atan2(path[1, 1] - path[0, 1], path[1, 0] - path[0, 0])
        assert abs(math.remainder(e.start_yaw - heading, math.tau)) <= math.radians(30) + 1e-4
        assert finder.island_of(e.start_position) == finder.largest_island


def test_same_seed_same_episodes_and_other_seeds_others(sample, apartment: Scene):
    finder, goals, drawn = sample
    again = _draw(finder, apartment.annotations, goals, count=25, seed=4)
    assert [e.model_dump() for e in again.episodes] == [e.model_dump() for e in drawn.episodes]
    other = _draw(finder, apartment.annotations, goals, count=25, seed=5)
    assert [e.start_position for e in other.episodes] != [e.start_position for e in drawn.episodes]


def test_indoor_to_outdoor_scenes_start_inside_the_building(sample, apartment: Scene):
    from shapely.geometry import Point, Polygon

    finder, goals, _ = sample
    indoor = [Polygon(p) for p in apartment.annotations.indoor_polygons]
    assert indoor, "the apartment has an indoor region"
    settings = SamplingSettings(start_region="indoor")
    drawn = _draw(finder, apartment.annotations, goals, count=10, seed=1, settings=settings)
    assert drawn.episodes
    assert all(any(p.contains(Point(e.start_position[:2])) for p in indoor) for e in drawn.episodes)


def test_impossible_lengths_give_up_and_say_how_often(sample, apartment: Scene):
    finder, goals, _ = sample
    settings = SamplingSettings(path_length=(200.0, 300.0), attempts=5)
    assert (settings.min_length, settings.max_length) == (200.0, 300.0)
    drawn = _draw(finder, apartment.annotations, goals, count=3, seed=0, settings=settings)
    assert drawn.episodes == [] and drawn.given_up == 3 and drawn.attempts == 15


def test_path_lengths_are_shortest_then_longest():
    with pytest.raises(ValueError, match=r"path_length must be \[shortest, longest\], got \[9.0, 3.0\]"):
        SamplingSettings(path_length=(9.0, 3.0))


class _SplitIslands:
    """A navmesh whose points north of `cut` (y) count as a second island, as a city cut in two by a
    railway: the building's floor is mostly on the south island, most goals on the north one."""

    def __init__(self, finder, cut: float) -> None:
        self._finder, self._cut = finder, cut

    def __getattr__(self, name: str):
        return getattr(self._finder, name)

    def island_of(self, point, **kwargs):
        real = np.asarray(self._finder.island_of(point, **kwargs))
        y = np.asarray(point, dtype=float).reshape(-1, 3)[:, 1]
        relabelled = np.where(real < 0, -1, (y > self._cut).astype(int))
        return int(relabelled[0]) if real.ndim == 0 else relabelled


def test_indoor_starts_come_from_the_island_the_building_stands_on(sample, apartment: Scene):
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    finder, goals, _ = sample
    region = unary_union([Polygon(p) for p in apartment.annotations.indoor_polygons])
    lo_y, hi_y = region.bounds[1], region.bounds[3]
    cut = lo_y + 0.7 * (hi_y - lo_y)  # the north island: a strip of the floor holding most goals
    north = [g for gs in goals.values() for g in gs if g.position[1] > cut + 2.0]
    south = min((g for gs in goals.values() for g in gs if g.position[1] < cut - 2.0), key=lambda g: g.object_id)
    assert len(north) >= 2, "the apartment's goals"  # more goal regions on the north island than one
    chosen: dict[str, list] = {}
    for goal in [south, *north]:
        chosen.setdefault(goal.category, []).append(goal)
    split = _SplitIslands(finder, cut)
    settings = SamplingSettings(start_region="indoor", path_length=(1.0, 50.0))
    drawn = _draw(split, apartment.annotations, chosen, count=6, seed=2, settings=settings)
    assert drawn.episodes, "starts on the building's island reach its goals"
    for episode in drawn.episodes:  # goals of the floor's island, not of the island with most goals
        assert [goal.object_id for goal in episode.goals] == [south.object_id]
