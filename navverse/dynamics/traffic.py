"""Cars driving the lanes of a street plan, keeping their distance and stopping for people on crossings.

The lanes come from the roads of a city map (centerline, width, ``lanes``, ``oneway``, ``highway``):
a two-way road gets half its lanes each way (at least one), a one-way road all of them along its
centerline, each lane offset to the right of its direction of travel (``driving_side="left"`` mirrors
it) by whole lane widths. A lane ends where its road does; the lanes starting within
:data:`JUNCTION_REACH` of that end are where a car may go next (a U-turn only at a dead end).

Each car follows its lane by arc length with the Intelligent Driver Model (Treiber, Hennecke and
Helbing 2000), the usual car-following law of microscopic traffic simulators: it accelerates towards
its road's speed, keeps a time gap to the car ahead (on its lane or the next it takes) and brakes
comfortably for a stop. A crossing on its lane with a person on it is a stop: the car halts
:data:`STOP_BEFORE` ahead of the crossing and goes on once the crossing is clear. Speeds are by road
class (:data:`SPEED_BY_HIGHWAY`, urban limits).

Every draw (where cars start, which lane they take at a junction) comes from one generator seeded by
the caller, in a fixed order: the same plan, people and seed give the same traffic.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

__all__ = [
    "JUNCTION_REACH",
    "SPEED_BY_HIGHWAY",
    "STOP_BEFORE",
    "CarState",
    "Lane",
    "RoadSpec",
    "Traffic",
    "lanes_of",
]

LANE_WIDTH = 3.25
"""Width (m) of one lane when a road's ``lanes`` is not given (its width divided by this)."""
JUNCTION_REACH = 4.0
"""Distance (m) between a lane's end and another's start within which a car can go on."""
STOP_BEFORE = 3.0
"""Where (m before a crossing's centre) a car halts for a person on it."""
CROSSING_HALF_WIDTH = 2.5
"""Half width (m) of a crosswalk along the road: a person within it, on the road, is on the crossing."""
CAR_LENGTH = 4.5
SPEED_BY_HIGHWAY: Mapping[str, float] = {
    "motorway": 22.0,
    "trunk": 16.7,
    "primary": 13.9,
    "secondary": 13.9,
    "tertiary": 11.1,
    "unclassified": 8.3,
    "residential": 8.3,
    "living_street": 2.8,
    "service": 4.2,
}
"""Speed (m/s) by OSM ``highway`` class: urban limits (50 km/h on main roads, 30 in residential
streets, walking pace in living streets); other classes drive at the residential speed."""
_DEFAULT_SPEED = SPEED_BY_HIGHWAY["residential"]

# Intelligent Driver Model parameters (urban driving).
_MAX_ACCELERATION = 1.5  # m/s²
_COMFORT_BRAKING = 2.0  # m/s²
_MIN_GAP = 2.0  # m, standstill distance to the car (or stop line) ahead
_TIME_GAP = 1.2  # s
_LOOKAHEAD = 60.0  # m, how far ahead leaders and crossings are looked for


@dataclass(frozen=True)
class RoadSpec:
    """A road of the street plan, as a city map gives it.

    Attributes
    ----------
    centerline : ndarray, shape (N, 2)
        Its centerline (m), in the direction of a one-way road's traffic.
    width : float
        Carriageway width (m).
    highway : str
        OSM ``highway`` class (sets the speed).
    lanes : int or None
        Lanes in both directions together, if mapped.
    oneway : bool
        Whether all lanes go along the centerline.
    """

    centerline: np.ndarray
    width: float
    highway: str = "residential"
    lanes: int | None = None
    oneway: bool = False


@dataclass(frozen=True)
class Lane:
    """One lane: the polyline a car's centre follows, its cumulative lengths and its speed.

    Attributes
    ----------
    points : ndarray, shape (N, 2)
    lengths : ndarray, shape (N,)
        Arc length at each point (0 at the start).
    speed : float
        Desired speed (m/s).
    road : int
        Index of its road.
    forward : bool
        Whether it runs along its road's centerline.
    road_width : float
        Width (m) of its road's carriageway.
    """

    points: np.ndarray
    lengths: np.ndarray
    speed: float
    road: int
    forward: bool
    road_width: float

    @property
    def length(self) -> float:
        """Arc length (m)."""
        return float(self.lengths[-1])

    def at(self, s: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """Positions ``(K, 2)`` and headings ``(K,)`` (radians) at arc lengths `s` (clamped to the lane)."""
        s = np.clip(np.atleast_1d(np.asarray(s, dtype=float)), 0.0, self.length)
        segment = np.clip(np.searchsorted(self.lengths, s, side="right") - 1, 0, len(self.points) - 2)
        start, end = self.points[segment], self.points[segment + 1]
        span = np.maximum(self.lengths[segment + 1] - self.lengths[segment], 1e-9)
        t = ((s - self.lengths[segment]) / span)[:, None]
        direction = end - start
        return start + t * direction, np.arctan2(direction[:, 1], direction[:, 0])

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Arc length of the point of the lane nearest each of `points` ``(K, 2)`` and the distance to
        it, as two ``(K,)`` arrays (a single point ``(2,)`` gives two floats)."""
        single = np.ndim(points) == 1
        xy = np.atleast_2d(np.asarray(points, dtype=float))[:, None, :]  # (K, 1, 2)
        start, end = self.points[:-1], self.points[1:]
        direction = end - start
        span2 = np.maximum((direction**2).sum(axis=1), 1e-12)
        t = np.clip(((xy - start) * direction).sum(axis=2) / span2, 0.0, 1.0)  # (K, S)
        distance = np.linalg.norm(start + t[..., None] * direction - xy, axis=2)
        best = np.argmin(distance, axis=1)
        rows = np.arange(len(best))
        along = self.lengths[best] + t[rows, best] * np.sqrt(span2[best])
        nearest = distance[rows, best]
        return (float(along[0]), float(nearest[0])) if single else (along, nearest)


def _offset_polyline(points: np.ndarray, offset: float) -> np.ndarray:
    """`points` moved `offset` to the right of their direction (mitred at the joints)."""
    direction = np.diff(points, axis=0)
    direction /= np.maximum(np.linalg.norm(direction, axis=1, keepdims=True), 1e-9)
    right = np.stack([direction[:, 1], -direction[:, 0]], axis=1)
    normals = np.vstack([right[:1], right[:-1] + right[1:], right[-1:]])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-9)
    cosine = np.ones(len(points))
    cosine[1:-1] = np.maximum((normals[1:-1] * right[:-1]).sum(axis=1), 0.5)
    return points + normals * (offset / cosine)[:, None]


def lanes_of(roads: Sequence[RoadSpec], *, driving_side: str = "right") -> list[Lane]:
    """The lanes of a street plan (see the module docstring).

    Raises
    ------
    ValueError
        If `driving_side` is neither ``"right"`` nor ``"left"``.
    """
    if driving_side not in ("right", "left"):
        raise ValueError(f"driving_side must be 'right' or 'left', got {driving_side!r}")
    side = 1.0 if driving_side == "right" else -1.0
    lanes: list[Lane] = []
    for index, road in enumerate(roads):
        centre = np.asarray(road.centerline, dtype=float)[:, :2]
        keep = np.concatenate([[True], np.linalg.norm(np.diff(centre, axis=0), axis=1) > 1e-6])
        centre = centre[keep]
        if len(centre) < 2:
            continue
        count = max(1, road.lanes if road.lanes else round(road.width / LANE_WIDTH))
        lane_width = road.width / count
        speed = SPEED_BY_HIGHWAY.get(road.highway, _DEFAULT_SPEED)
        if road.oneway:  # all lanes along the centerline, spread over the whole width
            ways = [(True, [(k + 0.5) * lane_width - road.width / 2.0 for k in range(count)])]
        else:  # half each way, each on the right of its own direction
            forward = max(1, count // 2)
            backward = max(1, count - count // 2)
            ways = [
                (True, [(k + 0.5) * lane_width for k in range(forward)]),
                (False, [(k + 0.5) * lane_width for k in range(backward)]),
            ]
        for forward_way, offsets in ways:
            path = centre if forward_way else centre[::-1]
            for offset in offsets:
                points = _offset_polyline(path, side * offset)
                lengths = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
                lanes.append(Lane(points, lengths, speed, index, forward_way, float(road.width)))
    return lanes


@dataclass(frozen=True)
class CarState:
    """Every car after a step.

    Attributes
    ----------
    positions : ndarray, shape (C, 2)
        Centre of each car (m).
    headings : ndarray, shape (C,)
        Direction of travel (radians from +x).
    speeds : ndarray, shape (C,)
        Speed (m/s).
    lanes : ndarray of int, shape (C,)
        The lane each is on.
    stopped_for_people : ndarray of bool, shape (C,)
        Cars held by a person on a crossing ahead.
    heights : ndarray, shape (C,)
        The road surface under each car (m).
    """

    positions: np.ndarray
    headings: np.ndarray
    speeds: np.ndarray
    lanes: np.ndarray
    stopped_for_people: np.ndarray
    heights: np.ndarray


class Traffic:
    """Cars on the lanes of a street plan.

    Parameters
    ----------
    lanes : sequence of Lane
        From :func:`lanes_of`.
    crossings : array_like, shape (K, 2)
        Crossing positions (m) on the roads.
    cars : int, keyword-only
        How many cars drive (fewer if the lanes are too short to hold them apart).
    seed : int, keyword-only
        Seed of where they start and the turns they take.
    height : callable, optional, keyword-only
        ``height(points (N, 2)) -> z (N,)``: the road surface under points, asked once for every lane
        point (cars' heights are interpolated along their lanes); None: 0.
    """

    def __init__(
        self,
        lanes: Sequence[Lane],
        crossings: np.ndarray,
        *,
        cars: int,
        seed: int,
        height: Callable[[np.ndarray], np.ndarray] | None = None,
    ) -> None:
        self.lanes = list(lanes)
        self._rng = np.random.default_rng(seed)
        self._next = self._successors()
        self._pack_lanes()
        self._heights = (
            np.asarray(height(self._points), dtype=float).reshape(-1)
            if height is not None and len(self._points)
            else np.zeros(len(self._points))
        )
        self._pack_stops(np.asarray(crossings, dtype=float).reshape(-1, 2))
        self._lane = np.zeros(0, dtype=np.int64)
        self._s = np.zeros(0)
        self._v = np.zeros(0)
        self._route = np.zeros(0, dtype=np.int64)  # the lane each car takes after its own (-1: none)
        self._held = np.zeros(0, dtype=bool)
        self._place(cars)

    def _successors(self) -> list[list[int]]:
        """For each lane, the lanes a car may take at its end (its own road's reverse only at a dead end)."""
        starts = np.array([lane.points[0] for lane in self.lanes]).reshape(-1, 2)
        result = []
        for lane in self.lanes:
            near = np.flatnonzero(np.linalg.norm(starts - lane.points[-1], axis=1) <= JUNCTION_REACH)
            onward = [int(j) for j in near if self.lanes[j].road != lane.road]
            result.append(onward or [int(j) for j in near])
        return result

    def _pack_lanes(self) -> None:
        """Every lane's points in one array, with a global arc length (lanes 1 m apart on it)."""
        lengths = np.array([lane.length for lane in self.lanes], dtype=float)
        self._length = lengths
        self._speed = np.array([lane.speed for lane in self.lanes], dtype=float)
        self._base = np.concatenate([[0.0], np.cumsum(lengths + 1.0)])[:-1]  # where each lane starts
        counts = np.array([len(lane.points) for lane in self.lanes], dtype=np.int64)
        self._first = np.concatenate([[0], np.cumsum(counts)])[:-1]  # its first point
        self._last_segment = self._first + counts - 2
        if self.lanes:
            self._points = np.concatenate([lane.points for lane in self.lanes])
            self._arc = np.concatenate(
                [lane.lengths + base for lane, base in zip(self.lanes, self._base, strict=True)]
            )
        else:
            self._points, self._arc = np.zeros((0, 2)), np.zeros(0)

    def _pack_stops(self, crossings: np.ndarray) -> None:
        """The crossings on each lane as flat arrays: lane, arc length, centre, the lane's direction there,
        sorted by lane and arc length; per lane its first row."""
        rows = []
        for index, lane in enumerate(self.lanes):
            if not len(crossings):
                break
            low, high = lane.points.min(axis=0) - lane.road_width, lane.points.max(axis=0) + lane.road_width
            near = np.flatnonzero(np.all((crossings >= low) & (crossings <= high), axis=1))
            if not len(near):
                continue
            along, distance = lane.project(crossings[near])
            keep = (distance <= lane.road_width) & (along > 0.0) & (along < lane.length)
            if keep.any():
                _, heading = lane.at(along[keep])
                for k, s, h in zip(near[keep], along[keep], heading, strict=True):
                    rows.append((index, float(s), *crossings[k], np.cos(h), np.sin(h), 0.5 * lane.road_width))
        table = np.array(sorted(rows), dtype=float).reshape(-1, 7)
        self._stop_lane = table[:, 0].astype(np.int64)
        self._stop_s = table[:, 1]
        self._stop_point = table[:, 2:4]
        self._stop_direction = table[:, 4:6]
        self._stop_half_road = table[:, 6]

    def _place(self, count: int) -> None:
        """Start `count` cars on lanes drawn by length, at least two car lengths apart."""
        lengths = self._length
        if not len(lengths) or lengths.sum() <= 0 or count <= 0:
            return
        lanes: list[int] = []
        positions: list[float] = []
        for _ in range(20 * count):
            if len(lanes) == count:
                break
            lane = int(self._rng.choice(len(lengths), p=lengths / lengths.sum()))
            s = float(self._rng.uniform(0.0, lengths[lane]))
            if any(
                l2 == lane and abs(s2 - s) < 2.0 * CAR_LENGTH for l2, s2 in zip(lanes, positions, strict=True)
            ):
                continue
            lanes.append(lane)
            positions.append(s)
        order = np.lexsort((positions, lanes))
        self._lane = np.array(lanes, dtype=np.int64)[order]
        self._s = np.array(positions)[order]
        self._v = self._speed[self._lane] * 0.5
        self._route = np.array([self._turn(int(i)) for i in self._lane], dtype=np.int64)
        self._held = np.zeros(len(self._lane), dtype=bool)

    def _turn(self, lane: int) -> int:
        """The lane a car takes after `lane` (-1: none, it will leave the plan)."""
        options = self._next[lane]
        return int(options[self._rng.integers(len(options))]) if options else -1

    def _gaps_ahead(self) -> tuple[np.ndarray, np.ndarray]:
        """Per car, the distance to the car ahead within the lookahead (on its lane, or first on the lane
        it takes next) and that car's speed; inf where none."""
        count = len(self._lane)
        gap, leader = np.full(count, np.inf), self._v.copy()
        if not count:
            return gap, leader
        order = np.lexsort((self._s, self._lane))
        lane, s = self._lane[order], self._s[order]
        same = lane[1:] == lane[:-1]
        behind = order[:-1][same]
        gap[behind] = s[1:][same] - s[:-1][same] - CAR_LENGTH
        leader[behind] = self._v[order[1:][same]]
        # The last car of each lane looks at the first car of the lane it takes next.
        last = np.ones(count, dtype=bool)
        last[:-1] = ~same
        first_of_lane = np.full(len(self.lanes), -1, dtype=np.int64)
        starts = np.ones(count, dtype=bool)
        starts[1:] = ~same
        first_of_lane[lane[starts]] = order[starts]
        tails = order[last]
        onward = self._route[tails]
        ahead = np.where(onward >= 0, first_of_lane[np.maximum(onward, 0)], -1)
        has = ahead >= 0
        distance = (
            self._length[self._lane[tails[has]]] - self._s[tails[has]] + self._s[ahead[has]] - CAR_LENGTH
        )
        close = distance < _LOOKAHEAD
        gap[tails[has][close]] = distance[close]
        leader[tails[has][close]] = self._v[ahead[has][close]]
        return gap, leader

    def _stops_ahead(self, people: np.ndarray) -> np.ndarray:
        """Per car, the distance to the stop line of the nearest crossing ahead (within the lookahead) with a
        person on it; inf where none."""
        stop = np.full(len(self._lane), np.inf)
        if not len(people) or not len(self._stop_s) or not len(self._lane):
            return stop
        # Only the people near a stop can be on it: pairs from a k-d tree of the people.
        reach = CROSSING_HALF_WIDTH + float(self._stop_half_road.max()) + 0.5
        near = cKDTree(people).query_ball_point(self._stop_point, r=reach)
        counts = np.fromiter((len(n) for n in near), dtype=np.int64, count=len(near))
        if not counts.any():
            return stop
        rows = np.repeat(np.arange(len(near)), counts)
        who = np.fromiter((i for n in near for i in n), dtype=np.int64, count=int(counts.sum()))
        offset = people[who] - self._stop_point[rows]
        direction = self._stop_direction[rows]
        along = np.abs((offset * direction).sum(axis=1))
        across = np.abs(offset[:, 0] * direction[:, 1] - offset[:, 1] * direction[:, 0])
        on_it = (along <= CROSSING_HALF_WIDTH) & (across <= self._stop_half_road[rows] + 0.5)
        occupied = np.zeros(len(self._stop_s), dtype=bool)
        occupied[rows[on_it]] = True
        busy = np.flatnonzero(occupied)
        if not len(busy):
            return stop
        # Pair every car with the busy stops of its lane.
        car_of, stop_of = np.nonzero(self._lane[:, None] == self._stop_lane[busy][None, :])
        ahead = self._stop_s[busy[stop_of]] - self._s[car_of]
        valid = (ahead >= STOP_BEFORE - 0.5) & (ahead <= _LOOKAHEAD)  # behind, or at it: the car goes on
        np.minimum.at(stop, car_of[valid], ahead[valid] - STOP_BEFORE)
        return stop

    def step(self, dt: float, *, people: np.ndarray | None = None) -> CarState:
        """Advance every car by `dt` seconds; `people` ``(P, 2)`` are where people stand (a person on a
        crossing holds the cars coming to it). Returns the cars' state after the step."""
        if not dt > 0.0:
            raise ValueError(f"a traffic step must be a positive time, got {dt}")
        crowd = np.zeros((0, 2)) if people is None else np.asarray(people, dtype=float).reshape(-1, 2)
        gap, leader = self._gaps_ahead()
        stop = self._stops_ahead(crowd)
        self._held = stop < gap
        gap = np.where(self._held, stop, gap)
        leader = np.where(self._held, 0.0, leader)
        acceleration = _idm(self._v, self._speed[self._lane], gap, leader)
        self._v = np.maximum(self._v + acceleration * dt, 0.0)
        self._s = self._s + self._v * dt
        for car in np.flatnonzero(self._s > self._length[self._lane]):
            while self._s[car] > self._length[self._lane[car]]:
                following = int(self._route[car])
                if following < 0:  # a lane to nowhere: the car comes back at a random lane's start
                    self._s[car] = 0.0
                    following = int(self._rng.integers(len(self.lanes)))
                else:
                    self._s[car] -= self._length[self._lane[car]]
                self._lane[car] = following
                self._route[car] = self._turn(following)
        return self.state()

    def state(self) -> CarState:
        """Where every car is."""
        lane = self._lane
        s = np.clip(self._s, 0.0, self._length[lane]) + self._base[lane]
        segment = np.searchsorted(self._arc, s, side="right") - 1
        segment = np.clip(segment, self._first[lane], self._last_segment[lane])
        start, end = self._points[segment], self._points[segment + 1]
        span = np.maximum(self._arc[segment + 1] - self._arc[segment], 1e-9)
        t = ((s - self._arc[segment]) / span)[:, None]
        direction = end - start
        positions = start + t * direction
        heights = self._heights[segment] + t[:, 0] * (self._heights[segment + 1] - self._heights[segment])
        headings = np.arctan2(direction[:, 1], direction[:, 0])
        return CarState(positions, headings, self._v.copy(), lane.copy(), self._held.copy(), heights)


def _idm(v: np.ndarray, v0: np.ndarray, gap: np.ndarray, leader: np.ndarray) -> np.ndarray:
    """The Intelligent Driver Model's acceleration of cars at speeds `v` wanting `v0`, `gap` meters
    behind something moving at `leader` (inf: a free road)."""
    free = 1.0 - (v / np.maximum(v0, 1e-6)) ** 4
    wanted = _MIN_GAP + np.maximum(
        0.0, v * _TIME_GAP + v * (v - leader) / (2.0 * np.sqrt(_MAX_ACCELERATION * _COMFORT_BRAKING))
    )
    interaction = np.where(np.isfinite(gap), (wanted / np.maximum(gap, 0.1)) ** 2, 0.0)
    return _MAX_ACCELERATION * (free - interaction)
