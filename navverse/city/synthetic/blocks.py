"""Blocks and buildings of synthetic cities: the land between the streets, parcelled along its edges.

A block is a face of the street network: the window minus every street (carriageway and sidewalks,
round-capped) and minus the water with its embankments (:func:`block_polygons`). A built block is
shrunk by the setback; its outline (counter-clockwise) is cut into *sides* where it turns by more
than 30°, and each side is walked from a random start: a parcel of a drawn frontage, its building a
rectangle whose front is the chord across the parcel (moved inward where the side bulges in, such as
along a ring road; narrower where it would bulge in more than 1 m) and whose depth is drawn, shrunk
or narrowed when it would leave the block or touch a building already placed, then a drawn gap
(:func:`frontage_lots`). Buildings therefore face
the street they stand on, never overlap each other (1 cm apart at least) and stay the setback away
from every sidewalk. A block's inside (its courtyard) is left open.
"""

from __future__ import annotations

import bisect
import itertools
import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry
from shapely.geometry.polygon import orient

from navverse.city.map import Polygon2, Road
from navverse.city.synthetic.params import SyntheticCityParams
from navverse.city.synthetic.streets import XY, Window

__all__ = [
    "FRONT_REACH",
    "Lot",
    "block_polygons",
    "frontage_lots",
    "polygon2",
    "polygons_of",
    "street_shapes",
]

CORNER_TURN = math.radians(30.0)
"""A block outline turning by more than this at a vertex starts a new side there."""
MIN_SIDE = 4.0
"""Smallest building width and depth (m)."""
MAX_BULGE = 1.0
"""Farthest a block outline may bulge in behind a building's front (m), along a curved street."""
SIMPLIFY = 0.1
"""Tolerance of the simplified block outline that is walked (m)."""
FRONT_REACH = MAX_BULGE + 2.0 * SIMPLIFY + 0.05
"""A building's front is at most the setback and this far from the block's edge (m)."""
BUILDING_GAP = 0.01
"""Least distance between two buildings (m), so rounding to the millimetre cannot make them overlap."""


def polygons_of(geometry: BaseGeometry) -> list[Polygon]:
    """The polygons of a geometry (a polygon, a multipolygon or a collection), in GEOS order."""
    if isinstance(geometry, Polygon):
        return [] if geometry.is_empty else [geometry]
    return [p for g in getattr(geometry, "geoms", []) for p in polygons_of(g)]


def _ring(coords: object) -> list[XY]:
    ring: list[XY] = []
    for x, y in list(coords)[:-1]:  # type: ignore[call-overload]
        point = (round(float(x), 3) + 0.0, round(float(y), 3) + 0.0)
        if not ring or point != ring[-1]:
            ring.append(point)
    while len(ring) > 1 and ring[0] == ring[-1]:
        ring.pop()
    return ring


def polygon2(polygon: Polygon) -> Polygon2 | None:
    """A map polygon of ``polygon``, millimetre coordinates (None when under 3 distinct points)."""
    exterior = _ring(polygon.exterior.coords)
    if len(set(exterior)) < 3:
        return None
    holes = [h for h in (_ring(i.coords) for i in polygon.interiors) if len(set(h)) >= 3]
    return Polygon2(exterior=exterior, holes=holes)


def street_shapes(roads: list[Road]) -> list[Polygon]:
    """Each road's carriageway and sidewalks: its centre line buffered by half the carriageway plus
    its wider sidewalk, round caps and joins."""
    return [
        shapely.buffer(
            shapely.linestrings(road.centerline.points),
            road.width / 2.0 + max(road.sidewalk_left or 0.0, road.sidewalk_right or 0.0),
        )
        for road in roads
    ]


def block_polygons(
    window: Window, streets: BaseGeometry, keepout: BaseGeometry, *, smallest: float
) -> list[Polygon]:
    """The faces of the street network: the window minus ``streets`` and ``keepout``, each at least
    ``smallest`` m², in a fixed order (by the lower-left corner of their bounds)."""
    land = box(*window).difference(shapely.union_all([streets, keepout]))
    blocks = [p for p in polygons_of(land) if p.area >= smallest]
    return sorted(blocks, key=lambda p: (round(p.bounds[1], 3), round(p.bounds[0], 3), round(p.area, 3)))


@dataclass(frozen=True)
class Lot:
    """A building's footprint: front start, front end, back end, back start (counter-clockwise);
    the front faces the street."""

    corners: tuple[XY, XY, XY, XY]

    @property
    def front(self) -> tuple[XY, XY]:
        """The street facade's end points."""
        return self.corners[0], self.corners[1]


def _sides(ring: list[XY]) -> list[list[XY]]:
    """A closed counter-clockwise ring cut at its corners into open polylines."""
    n = len(ring)
    corners = []
    for k in range(n):
        a, b, c = ring[k - 1], ring[k], ring[(k + 1) % n]
        ux, uy, vx, vy = b[0] - a[0], b[1] - a[1], c[0] - b[0], c[1] - b[1]
        if abs(math.atan2(ux * vy - uy * vx, ux * vx + uy * vy)) > CORNER_TURN:
            corners.append(k)
    if not corners:
        return [[*ring, ring[0]]]
    sides = []
    for start, end in itertools.pairwise([*corners, corners[0] + n]):
        sides.append([ring[k % n] for k in range(start, end + 1)])
    return sides


class _Side:
    """A polyline walked by distance from its start."""

    def __init__(self, points: list[XY]) -> None:
        self.points = points
        self.stations = [0.0]
        for a, b in itertools.pairwise(points):
            self.stations.append(self.stations[-1] + math.dist(a, b))
        self.length = self.stations[-1]

    def at(self, station: float) -> XY:
        k = min(max(bisect.bisect_right(self.stations, station) - 1, 0), len(self.points) - 2)
        a, b = self.points[k], self.points[k + 1]
        span = self.stations[k + 1] - self.stations[k]
        share = 0.0 if span <= 0.0 else (station - self.stations[k]) / span
        return a[0] + share * (b[0] - a[0]), a[1] + share * (b[1] - a[1])

    def between(self, start: float, end: float) -> list[XY]:
        """The polyline's vertices strictly between two stations."""
        return [p for p, s in zip(self.points, self.stations, strict=True) if start < s < end]


def _rectangle(side: _Side, start: float, width: float, depth: float) -> tuple[XY, XY, XY, XY] | None:
    p0, p1 = side.at(start), side.at(start + width)
    ux, uy = p1[0] - p0[0], p1[1] - p0[1]
    chord = math.hypot(ux, uy)
    if chord < MIN_SIDE:
        return None
    ux, uy = ux / chord, uy / chord
    nx, ny = -uy, ux  # inward: left of a counter-clockwise walk
    bulge = max(
        [0.0] + [(q[0] - p0[0]) * nx + (q[1] - p0[1]) * ny for q in side.between(start, start + width)]
    )
    if bulge > MAX_BULGE:
        return None  # too wide for the curve: a narrower front follows it better
    shift = bulge + SIMPLIFY + 0.02
    front0 = (p0[0] + nx * shift, p0[1] + ny * shift)
    front1 = (p1[0] + nx * shift, p1[1] + ny * shift)
    return (
        front0,
        front1,
        (front1[0] + nx * depth, front1[1] + ny * depth),
        (front0[0] + nx * depth, front0[1] + ny * depth),
    )


Bounds = tuple[float, float, float, float]


def _bounds(corners: tuple[XY, ...]) -> Bounds:
    xs, ys = [c[0] for c in corners], [c[1] for c in corners]
    return min(xs), min(ys), max(xs), max(ys)


def _blocker(shape: Polygon, bounds: Bounds, shapes: list[tuple[Polygon, Bounds]]) -> Polygon | None:
    """The first of ``shapes`` closer than :data:`BUILDING_GAP` to ``shape``, if any."""
    x0, y0, x1, y1 = bounds
    for other, (a0, b0, a1, b1) in shapes:
        if (
            a0 > x1 + BUILDING_GAP
            or a1 < x0 - BUILDING_GAP
            or b0 > y1 + BUILDING_GAP
            or b1 < y0 - BUILDING_GAP
        ):
            continue
        if other.distance(shape) < BUILDING_GAP:
            return other
    return None


def frontage_lots(rng: np.random.Generator, block: Polygon, params: SyntheticCityParams) -> list[Lot]:
    """Buildings along the edges of a built block (see the module docstring).

    Parameters
    ----------
    rng : numpy.random.Generator
        Draws each parcel's start, frontage, depth and the gaps.
    block : shapely.Polygon
        The block: land between the streets (sidewalks excluded).
    params : SyntheticCityParams
        ``setback``, ``frontage``, ``depth`` and ``gap``.

    Returns
    -------
    list of Lot
        Rectangular footprints, fronts on the block's edge, in walking order.
    """
    lots: list[Lot] = []
    shapes: list[tuple[Polygon, Bounds]] = []
    buildable = block.buffer(-params.setback, join_style="mitre") if params.setback > 0 else block
    low_f, high_f = sorted(params.frontage)
    low_d, high_d = sorted(params.depth)
    for part in polygons_of(buildable):
        if part.area < MIN_SIDE * MIN_SIDE:
            continue
        shapely.prepare(part)
        # The outline is walked simplified (fewer, longer sides); fronts step SIMPLIFY further in.
        walked = orient(part.simplify(SIMPLIFY), sign=1.0)
        if not isinstance(walked, Polygon) or walked.is_empty:
            continue
        ring = _ring(walked.exterior.coords)
        if len(ring) < 3:
            continue
        for points in _sides(ring):
            side = _Side(points)
            station = float(rng.uniform(0.0, params.gap)) if params.gap > 0 else 0.0
            while station + MIN_SIDE <= side.length:
                width = min(float(rng.uniform(low_f, high_f)), side.length - station)
                depth = float(rng.uniform(low_d, high_d))
                placed = None
                blocker: Polygon | None = None
                for w, d in (
                    (width, depth),
                    (width, 0.7 * depth),
                    (0.6 * width, depth),
                    (0.6 * width, 0.6 * depth),
                    (0.4 * width, depth),
                ):
                    if w < MIN_SIDE or d < MIN_SIDE:
                        continue
                    corners = _rectangle(side, station, w, d)
                    if corners is None:
                        continue
                    xs, ys = [c[0] for c in corners], [c[1] for c in corners]
                    if not shapely.intersects_xy(part, xs, ys).all():
                        continue  # a corner outside: cheaper to tell than the whole rectangle
                    shape = shapely.polygons(corners)
                    if not part.contains(shape):
                        continue
                    blocker = _blocker(shape, _bounds(corners), shapes)
                    if blocker is None:
                        placed, width = corners, w
                        break
                if placed is not None:
                    lots.append(Lot(placed))
                    shapes.append((shapely.polygons(placed), _bounds(placed)))
                    station += width + (float(rng.exponential(params.gap)) if params.gap > 0 else 0.0)
                    continue
                if blocker is not None:
                    # Skip past the building in the way, measured along the side's chord direction.
                    p0 = side.at(station)
                    p1 = side.at(min(side.length, station + 1.0))
                    ux, uy = p1[0] - p0[0], p1[1] - p0[1]
                    norm = math.hypot(ux, uy) or 1.0
                    ahead = max(
                        (x - p0[0]) * ux / norm + (y - p0[1]) * uy / norm for x, y in blocker.exterior.coords
                    )
                    station += max(1.0, ahead + BUILDING_GAP + 0.05)
                else:
                    station += 1.5
    return lots
