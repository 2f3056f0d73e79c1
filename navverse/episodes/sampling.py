"""Episode candidates sampled on a scene's navmesh (paper Appendix D.1).

For a scene:

1. **Goals.** Objects are grouped into goal categories by the recipe's rules (regular expressions over
   prim names or paths, :class:`~navverse.scene.categories.CategoryRule`; the first match wins, a rule
   without a category drops the object), else by their own category, kept when the category is in the
   recipe's list. Storefronts are the PlaceNav goals, by place category.
2. **Goal regions.** An instance is reached where the goal distance (:func:`navverse.dataset.goal_distance`,
   3-D, of the robot's base standing there) is within the success distance ``1.0 + r_robot``: its region
   is the navmesh points there, found by snapping rings of points around the instance onto the navmesh.
3. **Episodes.** A goal category is drawn uniformly among those with a reachable instance, a start
   uniformly on the island that holds the goal regions (inside the indoor region for indoor-to-outdoor
   scenes, drawn near it on the island the region stands on, whose goals are then the instances
   outdoors), and the shortest path from the
   start to every instance's region is computed; instances whose path is 5-50 m long are kept, and an
   episode needs one. The reference path is the one to the
   closest kept instance; the start faces its next corner, turned by a uniform ±30°.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Annotated, Literal

import numpy as np
import shapely
from pydantic import Field, model_validator

from navverse.nav.pathfinder import PathFinder
from navverse.records.schema import Episode, EpisodeInfo, Goal, success_distance
from navverse.scene.annotations import SceneAnnotations
from navverse.scene.categories import CategoryRule, assign_category
from navverse.scene_types import scene_profile
from navverse.settings import Settings

__all__ = [
    "GoalRegion",
    "SamplingSettings",
    "SceneSample",
    "goal_regions",
    "object_goals",
    "place_goals",
    "sample_scene_episodes",
]

_RING_STEP = 0.2  # m between rings of candidate region points
_RING_POINTS = 24


PathLength = Annotated[float, Field(gt=0.0, le=1000.0, description="Meters, more than 0, at most 1000.")]
"""A path length (m), more than 0, at most 1000."""


class SamplingSettings(Settings):
    """How candidates are drawn: the accepted path lengths, the start's yaw, the attempts per episode
    and where starts may be. The robot's radius and base height are the embodiment's, given to
    :func:`sample_scene_episodes` beside these."""

    path_length: tuple[PathLength, PathLength] = (5.0, 50.0)
    """Accepted shortest-path lengths from the start to a goal instance's region: [shortest, longest]
    (m)."""
    yaw_jitter_deg: Annotated[float, Field(ge=0.0, le=180.0)] = 30.0
    """The start faces the reference path's next corner, plus a uniform turn within ± this (degrees)."""
    attempts: Annotated[int, Field(ge=1, le=10_000)] = 50
    """Starts drawn per episode before the episode is given up."""
    start_region: Literal["auto", "anywhere", "indoor"] = "auto"
    """Where starts may be: ``indoor`` inside the scene's indoor region; ``auto`` follows the scene
    type's profile (:mod:`navverse.scene_types`: ``indoor`` for indoor-to-outdoor scenes, else
    ``anywhere``)."""

    @model_validator(mode="after")
    def _ordered_lengths(self) -> SamplingSettings:
        if self.path_length[0] >= self.path_length[1]:
            raise ValueError(f"path_length must be [shortest, longest], got {list(self.path_length)}")
        return self

    @property
    def min_length(self) -> float:
        """The shortest accepted path (m)."""
        return self.path_length[0]

    @property
    def max_length(self) -> float:
        """The longest accepted path (m)."""
        return self.path_length[1]


@dataclass(frozen=True)
class GoalRegion:
    """A goal instance and the navmesh points from which it counts as reached."""

    goal: Goal
    points: np.ndarray  # (K, 3) snapped navmesh points within the success distance
    island: int


@dataclass
class SceneSample:
    """The candidates of one scene and what happened while drawing them."""

    episodes: list[Episode]
    categories: dict[str, int]  # reachable instances per goal category
    attempts: int = 0
    given_up: int = 0


def object_goals(
    annotations: SceneAnnotations,
    *,
    rules: Sequence[CategoryRule] = (),
    categories: Sequence[str] | None = None,
    hits: list[int] | None = None,
) -> dict[str, list[Goal]]:
    """Object goal instances by goal category.

    Parameters
    ----------
    annotations : SceneAnnotations
        The scene's objects.
    rules : sequence of CategoryRule
        Tried in order on each object's prim name and path; the first match names (or, with no
        category, drops) the object; objects no rule matches keep their own category.
    categories : sequence of str, optional
        Goal categories kept (default: all).
    hits : list of int, optional
        One counter per rule, incremented by the objects it matches.
    """
    keep = None if categories is None else set(categories)
    goals: dict[str, list[Goal]] = {}
    for obj in annotations.objects:
        name = obj.prim_path.rsplit("/", 1)[-1]
        category = assign_category(rules, name=name, path=obj.prim_path, default=obj.category, hits=hits)
        if category is None or (keep is not None and category not in keep):
            continue
        goals.setdefault(category, []).append(
            Goal(
                object_id=obj.id,
                category=category,
                position=_round3(obj.center),
                radius=round(obj.goal_radius, 4),
                size=_round3(obj.size),
            )
        )
    return dict(sorted(goals.items()))


def place_goals(
    annotations: SceneAnnotations, *, categories: Sequence[str] | None = None
) -> dict[str, list[Goal]]:
    """Storefront goal instances by place category: the entrance, with half the storefront's width."""
    keep = None if categories is None else set(categories)
    goals: dict[str, list[Goal]] = {}
    for store in annotations.storefronts:
        if keep is not None and store.place_category not in keep:
            continue
        goals.setdefault(store.place_category, []).append(
            Goal(
                object_id=store.id,
                category=store.place_category,
                position=_round3(store.entrance),
                radius=round(0.5 * store.size[0], 4),
                size=_round3(store.size),
            )
        )
    return dict(sorted(goals.items()))


def goal_regions(
    finder: PathFinder, goals: Sequence[Goal], *, success: float, base_height: float = 0.55
) -> list[GoalRegion]:
    """The navmesh points from which a robot base ``base_height`` above them is within the success
    distance of each goal (goals with none are left out)."""
    regions = []
    for goal in goals:
        cx, cy, cz = goal.position
        bottom = cz - goal.size[2] / 2.0
        radii = np.arange(max(goal.radius, 0.05), goal.radius + success, _RING_STEP)
        angles = np.linspace(0.0, 2.0 * math.pi, _RING_POINTS, endpoint=False)
        ring = np.array([[cx + r * math.cos(a), cy + r * math.sin(a), bottom] for r in radii for a in angles])
        # Down to the floor under furniture tops (a laptop on a desk), up a little for raised floors.
        snapped = finder.snap_point(ring, max_horizontal=_RING_STEP, max_vertical=1.5)
        snapped = snapped[np.isfinite(snapped).all(axis=1)]
        if len(snapped) == 0:
            continue
        base = snapped + np.array([0.0, 0.0, base_height])
        distance = np.maximum(np.linalg.norm(base - goal.position, axis=1) - goal.radius, 0.0)
        snapped = snapped[(distance <= success - 0.05) & finder.is_navigable(snapped)]  # not on a border
        if len(snapped) == 0:
            continue
        snapped = np.unique(snapped, axis=0)
        islands = finder.island_of(snapped)
        island = int(np.bincount(islands[islands >= 0]).argmax()) if (islands >= 0).any() else -1
        if island < 0:
            continue
        regions.append(GoalRegion(goal, snapped[islands == island], island))
    return regions


def _round3(values: Sequence[float]) -> tuple[float, float, float]:
    return (round(float(values[0]), 4), round(float(values[1]), 4), round(float(values[2]), 4))


def _indoor_floor(annotations: SceneAnnotations) -> float:
    """Height of the lowest floor of the scene's indoor buildings (0 without one)."""
    return min((b.base_height for b in annotations.buildings if b.indoor), default=0.0)


def _indoor_start(
    finder: PathFinder, annotations: SceneAnnotations, rng: np.random.Generator
) -> np.ndarray | None:
    """A navmesh point drawn near the indoor region (a city around it would make a uniform draw over
    the whole navmesh land inside almost never); None if the scene has no indoor region."""
    polygons = annotations.indoor_polygons
    if not polygons:
        return None
    corners = np.array([p for polygon in polygons for p in polygon], dtype=np.float64)
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    centre = (lo + hi) / 2.0
    floor = _indoor_floor(annotations)
    radius = float(np.linalg.norm(hi - lo) / 2.0)
    return finder.get_random_navigable_point_near((centre[0], centre[1], floor), radius, rng)


def _indoor_island(finder: PathFinder, annotations: SceneAnnotations) -> int | None:
    """The navmesh island most of the indoor region's floor is on (a lattice of at most ~4,000 points
    over it, snapped at the floor's height); None if the scene has no indoor region or none of it is
    on the navmesh."""
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    polygons = annotations.indoor_polygons
    if not polygons:
        return None
    region = unary_union([Polygon(p) for p in polygons])
    step = max(0.5, math.sqrt(region.area / 4000.0))
    lo_x, lo_y, hi_x, hi_y = region.bounds
    xs, ys = np.meshgrid(np.arange(lo_x + step / 2, hi_x, step), np.arange(lo_y + step / 2, hi_y, step))
    inside = shapely.contains_xy(region, xs.ravel(), ys.ravel())
    if not inside.any():
        return None
    floor = _indoor_floor(annotations)
    points = np.column_stack([xs.ravel()[inside], ys.ravel()[inside], np.full(int(inside.sum()), floor)])
    found = np.asarray(finder.island_of(points))
    found = found[found >= 0]
    return int(np.bincount(found).argmax()) if len(found) else None


def _indoor_reach(annotations: SceneAnnotations, distance: float):
    """Where a path of at most `distance` from inside the indoor region can end (a straight line's
    reach: paths are never shorter)."""
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    reach = unary_union([Polygon(p) for p in annotations.indoor_polygons]).buffer(distance)
    shapely.prepare(reach)
    return reach


def _inside_indoor(annotations: SceneAnnotations, point: np.ndarray) -> bool:
    from shapely.geometry import Point, Polygon

    p = Point(float(point[0]), float(point[1]))
    return any(Polygon(polygon).contains(p) for polygon in annotations.indoor_polygons)


def sample_scene_episodes(
    finder: PathFinder,
    annotations: SceneAnnotations,
    goals_by_category: dict[str, list[Goal]],
    *,
    task: str,
    count: int,
    rng: np.random.Generator,
    robot_radius: float,
    base_height: float,
    settings: SamplingSettings | None = None,
    id_offset: int = 0,
) -> SceneSample:
    """Draw up to ``count`` candidate episodes of one task in one scene.

    Parameters
    ----------
    finder : PathFinder
        The scene's navmesh.
    annotations : SceneAnnotations
        The scene's annotations (id, type, indoor region).
    goals_by_category : dict
        Goal instances by category (:func:`object_goals` or :func:`place_goals`).
    task : str
        ``objnav``, ``vln`` or ``placenav``.
    count : int
        Episodes wanted.
    rng : numpy.random.Generator
        All randomness.
    robot_radius : float
        ``r_robot`` of the embodiment: the success distance is ``1.0 + r_robot``.
    base_height : float
        Height of the embodiment's base above the ground when standing (m): goal distances are
        measured from the base.
    settings : SamplingSettings, optional
        Path lengths, start yaw, attempts, start region (default: the defaults).
    id_offset : int
        First episode number (ids are ``<scene_id>-<task>-<number:04d>``).

    Returns
    -------
    SceneSample
        Fewer than ``count`` episodes when the scene cannot give more (every category's attempts used).
    """
    settings = settings or SamplingSettings()
    success = success_distance(robot_radius, scene_type=annotations.scene_type)
    regions_by_category: dict[str, list[GoalRegion]] = {}
    for category, goals in goals_by_category.items():
        regions = goal_regions(finder, goals, success=success, base_height=base_height)
        if regions:
            regions_by_category[category] = regions
    sample = SceneSample(episodes=[], categories={c: len(r) for c, r in regions_by_category.items()})
    if not regions_by_category or count <= 0:
        return sample
    indoor_only = settings.start_region == "indoor" or (
        settings.start_region == "auto" and scene_profile(annotations.scene_type).start_region == "indoor"
    )
    # Starts come from the island that holds the most goal regions (the building's floor), or, when
    # they are drawn indoors, from the island the indoor region stands on: in a city cut in two by a
    # railway the other side may hold more goals than the side of the building.
    islands = np.bincount([r.island for rs in regions_by_category.values() for r in rs])
    island = int(islands.argmax())
    if indoor_only:
        floor_island = _indoor_island(finder, annotations)
        island = island if floor_island is None else floor_island
    categories = sorted(c for c, rs in regions_by_category.items() if any(r.island == island for r in rs))
    if indoor_only and scene_profile(annotations.scene_type).goals_outside:  # the goals are outdoors
        reach = _indoor_reach(annotations, settings.max_length)
        outdoor = {
            c: [
                r
                for r in rs
                if not _inside_indoor(annotations, np.asarray(r.goal.position))
                and shapely.intersects_xy(reach, r.points[:, 0], r.points[:, 1]).any()
            ]
            for c, rs in regions_by_category.items()
        }
        categories = [c for c in categories if any(r.island == island for r in outdoor[c])]
        regions_by_category = outdoor
        sample.categories = {c: len(rs) for c, rs in outdoor.items() if rs}
        if not categories:  # no goal outdoors within reach of the building
            return sample
    number = id_offset
    for _ in range(count):
        category = categories[int(rng.integers(len(categories)))]
        regions = [r for r in regions_by_category[category] if r.island == island]
        episode = None
        for _ in range(settings.attempts):
            sample.attempts += 1
            start = _indoor_start(finder, annotations, rng) if indoor_only else None
            if start is None:
                start = finder.get_random_navigable_point(rng, island=island)
            if indoor_only and not _inside_indoor(annotations, start):
                continue
            episode = _episode(finder, annotations, start, regions, task, number, rng, settings, success)
            if episode is not None:
                break
        if episode is None:
            sample.given_up += 1
            continue
        sample.episodes.append(episode)
        number += 1
    return sample


def _episode(
    finder: PathFinder,
    annotations: SceneAnnotations,
    start: np.ndarray,
    regions: Sequence[GoalRegion],
    task: str,
    number: int,
    rng: np.random.Generator,
    settings: SamplingSettings,
    success: float,
) -> Episode | None:
    """The episode from ``start`` to the instances of a category; None when no instance is in range."""
    kept: list[tuple[float, GoalRegion, np.ndarray]] = []
    for region in regions:
        if np.linalg.norm(region.points - start, axis=1).min() > settings.max_length + 1e-6:
            continue  # a path is never shorter than the straight line: out of range, no search needed
        path = finder.find_path_multi(start, region.points)
        if path.found and settings.min_length <= path.geodesic_distance <= settings.max_length:
            kept.append((path.geodesic_distance, region, path.points))
    if not kept:
        return None
    kept.sort(key=lambda item: (item[0], item[1].goal.object_id))
    length, closest, points = kept[0]
    heading = points[1, :2] - points[0, :2]
    yaw = math.atan2(heading[1], heading[0]) + math.radians(
        float(rng.uniform(-settings.yaw_jitter_deg, settings.yaw_jitter_deg))
    )
    category = closest.goal.category
    place = task == "placenav"
    goal_xy = np.asarray(closest.goal.position[:2])
    return Episode(
        episode_id=f"{annotations.scene_id}-{task}-{number:04d}",
        scene_id=annotations.scene_id,
        scene_type=annotations.scene_type,
        task=task,
        start_position=_round3(points[0]),
        start_rotation=(0.0, 0.0, round(math.sin(yaw / 2.0), 6), round(math.cos(yaw / 2.0), 6)),
        object_category=None if place else category,
        place_category=category if place else None,
        goals=[region.goal for _, region, _ in sorted(kept, key=lambda item: item[1].goal.object_id)],
        reference_path=[_round3(p) for p in points],
        info=EpisodeInfo(
            geodesic_distance=round(length, 4),
            euclidean_distance=round(float(np.linalg.norm(goal_xy - points[0, :2])), 4),
            closest_goal_object_id=closest.goal.object_id,
            success_distance=success,
        ),
    )
