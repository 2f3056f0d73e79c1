"""People walking a scene's sidewalks, crosswalks and squares, seeded per episode.

:class:`Pedestrians` fills a scene with walkers of :data:`~navverse.dynamics.crowd.PEDESTRIAN` at a
density per square meter of the areas people walk (sidewalks and crosswalks by default), each going
from its spawn point to a destination drawn on those areas, then to another when it arrives: trips
of ``trip_length`` meters as the crow flies, on the island of the navmesh it stands on. DetourCrowd
(:mod:`navverse.dynamics.crowd`) plans and steers them: they keep off roads and cross on crosswalks,
and avoid each other and any body added to the same crowd (the robot). Where they spawn can be kept
out of sight of a point (the robot's start): a ``visible`` test gives, for candidate points, whether
the point is seen from there, and those that are drawn again.

Every draw comes from one ``numpy`` generator seeded by the caller (an episode's seed), in a fixed
order, so the same scene, settings and seed give the same people on the same trips.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from navverse.dynamics.crowd import PEDESTRIAN, Crowd, CrowdState, TargetState, WalkerKind
from navverse.nav.pathfinder import PathFinder

__all__ = ["PedestrianSettings", "Pedestrians", "WalkableAreas"]

ARRIVED = 0.6
"""Distance (m) to its destination at which a pedestrian picks the next one."""
_SPAWN_TRIES = 50


@dataclass(frozen=True)
class PedestrianSettings:
    """How many people walk a scene and where.

    Attributes
    ----------
    density : float
        People per 1000 m² of the areas they walk (``areas``); 5 puts about 100 in a 500 m window of a
        dense city (some 20,000 m² of sidewalk).
    max_people : int
        The most people in one scene, whatever its area.
    areas : tuple of str
        The area names (terrain classes) where people spawn and go.
    trip_length : tuple of float
        Range (m) of the straight-line distance from one destination to the next.
    """

    density: float = 5.0
    max_people: int = 150
    areas: tuple[str, ...] = ("sidewalk", "crosswalk")
    trip_length: tuple[float, float] = (15.0, 80.0)

    def __post_init__(self) -> None:
        if not self.density >= 0.0:
            raise ValueError(f"density must be 0 or more people per 1000 m², got {self.density}")
        if self.max_people < 0:
            raise ValueError(f"max_people must be 0 or more, got {self.max_people}")
        low, high = self.trip_length
        if not 0.0 < low <= high:
            raise ValueError(f"trip_length must be (low, high) with 0 < low <= high, got {self.trip_length}")


class WalkableAreas:
    """The navmesh polygons of some areas, for drawing points uniformly over them.

    Parameters
    ----------
    finder : PathFinder
        A navmesh whose areas have names (a scene's terrain classes).
    areas : sequence of str
        The area names drawn from; names the navmesh does not have are ignored.
    """

    def __init__(self, finder: PathFinder, areas: Sequence[str]) -> None:
        ids = {finder.area_names[a] for a in areas if a in finder.area_names}
        polygons = finder.polygons()
        kinds = finder.polygon_area_types()
        triangles = []
        for polygon, kind in zip(polygons, kinds, strict=True):
            if int(kind) in ids and len(polygon) >= 3:
                triangles.extend((polygon[0], polygon[i], polygon[i + 1]) for i in range(1, len(polygon) - 1))
        self._triangles = np.asarray(triangles, dtype=float).reshape(-1, 3, 3)
        edges = self._triangles[:, 1:, :2] - self._triangles[:, :1, :2]
        areas_m2 = 0.5 * np.abs(edges[:, 0, 0] * edges[:, 1, 1] - edges[:, 0, 1] * edges[:, 1, 0])
        self.area_m2 = float(areas_m2.sum())
        """Total area (m²)."""
        self._cumulative = np.cumsum(areas_m2) / max(self.area_m2, 1e-12)
        centres = self._triangles.mean(axis=1)
        self._island = np.asarray(finder.island_of(centres), dtype=int) if len(centres) else np.zeros(0, int)

    def draw(self, rng: np.random.Generator, count: int, *, island: int | None = None) -> np.ndarray:
        """`count` points ``(count, 3)`` uniform over the areas (of one island, if given); empty if none."""
        if not len(self._triangles) or count <= 0:
            return np.zeros((0, 3))
        if island is None:
            cumulative, triangles = self._cumulative, self._triangles
        else:
            keep = self._island == island
            if not keep.any():
                return np.zeros((0, 3))
            triangles = self._triangles[keep]
            weights = np.diff(self._cumulative, prepend=0.0)[keep]
            cumulative = np.cumsum(weights) / weights.sum()
        which = np.minimum(np.searchsorted(cumulative, rng.random(count), side="right"), len(triangles) - 1)
        u, v = rng.random(count), rng.random(count)
        flip = u + v > 1.0
        u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
        a, b, c = triangles[which, 0], triangles[which, 1], triangles[which, 2]
        return a + u[:, None] * (b - a) + v[:, None] * (c - a)


class Pedestrians:
    """People walking a scene, with destinations drawn from one seeded generator.

    Parameters
    ----------
    finder : PathFinder
        The scene's navmesh with named areas (``load_scene_navmesh``).
    settings : PedestrianSettings, optional
        Density, areas and trips (default: :class:`PedestrianSettings` as declared).
    seed : int, keyword-only
        Seed of every draw (spawn points, destinations).
    visible : callable, optional, keyword-only
        ``visible(points (K, 3)) -> bool (K,)``: points that may not hold a person at the start (seen
        from the robot's start); they are drawn again, up to a bound, else left out.
    others : sequence of WalkerKind, keyword-only
        Further kinds the same crowd holds (the robot's body), added by the caller with
        :attr:`crowd`.
    extra_slots : int, keyword-only
        Slots kept free for those.
    """

    def __init__(
        self,
        finder: PathFinder,
        settings: PedestrianSettings | None = None,
        *,
        seed: int,
        visible: Callable[[np.ndarray], np.ndarray] | None = None,
        others: Sequence[WalkerKind] = (),
        extra_slots: int = 1,
    ) -> None:
        settings = settings or PedestrianSettings()
        self.settings = settings
        self._rng = np.random.default_rng(seed)
        self._walkable = WalkableAreas(finder, settings.areas)
        wanted = min(settings.max_people, round(settings.density * self._walkable.area_m2 / 1000.0))
        self.crowd = Crowd(finder, [PEDESTRIAN, *others], max_agents=max(1, wanted + extra_slots))
        self.people: list[int] = []
        """Crowd slots of the people, in the order they were placed."""
        self._targets = np.full((self.crowd.max_agents, 3), np.nan)  # per crowd slot; NaN: no trip
        self._islands: dict[int, int] = {}
        for point in self._spawn_points(wanted, visible):
            agent = self.crowd.add(point, PEDESTRIAN.name)
            if agent is None:
                continue
            self.people.append(agent)
            self._islands[agent] = int(finder.island_of(point[None])[0])
            self._next_trip(agent, point)

    def _spawn_points(self, count: int, visible: Callable[[np.ndarray], np.ndarray] | None) -> np.ndarray:
        """`count` spawn points, each drawn again while `visible` says it is seen."""
        points = self._walkable.draw(self._rng, count)
        if visible is None or not len(points):
            return points
        for _ in range(_SPAWN_TRIES):
            seen = np.asarray(visible(points), dtype=bool)
            if not seen.any():
                return points
            points[seen] = self._walkable.draw(self._rng, int(seen.sum()))
        return points[~np.asarray(visible(points), dtype=bool)]

    def _next_trip(self, agent: int, here: np.ndarray) -> None:
        """Send a person to a destination ``trip_length`` away on its island (the nearest such draw)."""
        low, high = self.settings.trip_length
        candidates = self._walkable.draw(self._rng, 8, island=self._islands[agent])
        if not len(candidates):
            return
        distance = np.linalg.norm(candidates[:, :2] - here[:2], axis=1)
        fitting = np.flatnonzero((distance >= low) & (distance <= high))
        target = candidates[fitting[0]] if len(fitting) else candidates[int(np.argmax(distance <= high))]
        if self.crowd.walk_to(agent, target):
            self._targets[agent] = target

    def step(self, dt: float) -> CrowdState:
        """Advance everyone by `dt` seconds; a person at its destination (or whose trip failed) sets off
        on the next one. Returns the crowd's state after the step."""
        self.crowd.step(dt)
        state = self.crowd.state()
        if not self.people:
            return state
        ids = np.asarray(self.people)
        targets = self._targets[ids]
        distance = np.hypot(*(state.positions[ids, :2] - targets[:, :2]).T)
        due = ~(distance >= ARRIVED)  # arrived, or no destination (NaN)
        for k in np.flatnonzero(~due):
            due[k] = self.crowd.target_state(self.people[k]) == TargetState.FAILED
        for k in np.flatnonzero(due):
            self._next_trip(self.people[k], state.positions[ids[k]])
        return state

    @property
    def walkable_area_m2(self) -> float:
        """Area (m²) of the areas people walk in this scene."""
        return self._walkable.area_m2
