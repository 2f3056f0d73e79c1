"""Road markings from the city map: centre lines, lane lines and edge lines on the carriageways.

Each mapped road gives its centre line, carriageway width, lanes and direction. :func:`road_markings`
lays a raster (:data:`MARKING_CELL` cells) over the roads that says which road segment is nearest each
place on a carriageway, and where two carriageways overlap (junctions: no lines there). At a hit on
a road, :meth:`RoadMarkings.painted` measures the point along its segment (from the road's start, so
dashes run on from one segment to the next) and across it, and paints:

- lane lines between the lanes, dashed (3 m of line, 6 m of gap), 12 cm wide; on a two-way road the
  middle one is the centre line (on a two-way road without a lane count, a centre line when the
  carriageway is at least :data:`CENTRE_LINE_WIDTH` wide);
- edge lines, solid, 25 cm inside each edge of main roads (:data:`EDGE_LINE_ROADS`).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise

import numpy as np
import shapely
from PIL import Image, ImageDraw
from shapely.geometry import LineString

__all__ = ["CENTRE_LINE_WIDTH", "EDGE_LINE_ROADS", "MARKING_CELL", "RoadMarkings", "road_markings"]

MARKING_CELL = 0.5
"""Side of a cell of the marking raster (m)."""
CENTRE_LINE_WIDTH = 5.5
"""Carriageway width (m) from which a two-way road without a lane count gets a centre line."""
EDGE_LINE_ROADS = frozenset({"motorway", "trunk", "primary", "secondary", "motorway_link", "trunk_link"})
"""Road classes (``highway=*``) with solid edge lines."""
_LINE = 0.12  # line width (m)
_DASH, _GAP = 3.0, 6.0
_EDGE_INSET = 0.25


@dataclass(frozen=True)
class MarkedRoad:
    """What a road's markings need: its carriageway width, lanes, direction and class."""

    centerline: tuple[tuple[float, float], ...]
    width: float
    lanes: int | None
    oneway: bool
    highway: str


@dataclass(frozen=True, eq=False)
class RoadMarkings:
    """The marking raster and the segments of the marked roads (see the module's docstring).

    Attributes
    ----------
    origin : ndarray, shape (2,)
        World xy of the raster's lower-left corner.
    raster : ndarray of int32, shape (rows, cols)
        Nearest segment per cell (``-1``: no carriageway, or a junction).
    segments : ndarray of float64, shape (S, 9)
        ``ax, ay, dx, dy, length, start (along the road), width, lane lines, edge lines`` per
        segment: its start, unit direction, length, distance of its start from the road's start, the
        carriageway width, the number of lanes the lines divide it into (0: no lane lines), and 1
        where it has edge lines.
    """

    origin: np.ndarray
    raster: np.ndarray
    segments: np.ndarray

    def painted(self, points: np.ndarray) -> np.ndarray:
        """Whether each world point ``(K, 3)`` on a carriageway lies on a painted line."""
        if len(self.segments) == 0 or len(points) == 0:
            return np.zeros(len(points), dtype=bool)
        rows, cols = self.raster.shape
        col = np.floor((points[:, 0] - self.origin[0]) / MARKING_CELL).astype(np.int64)
        row = np.floor((points[:, 1] - self.origin[1]) / MARKING_CELL).astype(np.int64)
        inside = (col >= 0) & (col < cols) & (row >= 0) & (row < rows)
        segment = np.full(len(points), -1, dtype=np.int64)
        segment[inside] = self.raster[row[inside], col[inside]]
        on = np.flatnonzero(segment >= 0)
        seg = self.segments.take(segment[on], axis=0)
        rx, ry = points[on, 0] - seg[:, 0], points[on, 1] - seg[:, 1]
        along = seg[:, 5] + rx * seg[:, 2] + ry * seg[:, 3]
        across = seg[:, 2] * ry - seg[:, 3] * rx  # left of the direction is positive
        width, lanes = seg[:, 6], seg[:, 7]
        dashed = np.mod(along, _DASH + _GAP) < _DASH
        lane_width = width / np.maximum(lanes, 1.0)
        position = (across + 0.5 * width) / lane_width
        nearest = np.clip(np.round(position), 1.0, np.maximum(lanes - 1.0, 1.0))
        lane_line = (lanes >= 2.0) & (np.abs(position - nearest) * lane_width < 0.5 * _LINE) & dashed
        edge = (seg[:, 8] > 0.0) & (np.abs(np.abs(across) - (0.5 * width - _EDGE_INSET)) < 0.5 * _LINE)
        painted = np.zeros(len(points), dtype=bool)
        painted[on] = lane_line | edge
        return painted


def _rasterize(
    polygon: shapely.Geometry, origin: np.ndarray, shape: tuple[int, int]
) -> tuple[tuple[slice, slice], np.ndarray]:
    """The raster cells whose centres `polygon` covers: the window of its bounds, and the mask there."""
    rows, cols = shape
    x0, y0, x1, y1 = polygon.bounds
    c0, c1 = (
        max(int((x0 - origin[0]) / MARKING_CELL), 0),
        min(int(np.ceil((x1 - origin[0]) / MARKING_CELL)) + 1, cols),
    )
    r0, r1 = (
        max(int((y0 - origin[1]) / MARKING_CELL), 0),
        min(int(np.ceil((y1 - origin[1]) / MARKING_CELL)) + 1, rows),
    )
    image = Image.new("1", (max(c1 - c0, 1), max(r1 - r0, 1)), 0)
    draw = ImageDraw.Draw(image)
    for part in getattr(polygon, "geoms", [polygon]):
        for ring, fill in [(part.exterior, 1)] + [(hole, 0) for hole in part.interiors]:
            xy = (
                (np.asarray(ring.coords) - origin) / MARKING_CELL - [c0, r0] - 0.5
            )  # cell centres at integers
            draw.polygon([tuple(p) for p in xy], fill=fill)
    return (slice(r0, r1), slice(c0, c1)), np.asarray(image, dtype=bool)[: r1 - r0, : c1 - c0]


def _lanes(road: MarkedRoad) -> int:
    """How many lanes the lines divide a road into (0: no lines)."""
    if road.lanes is not None and road.lanes >= 1:
        return road.lanes if road.lanes >= 2 else 0
    if not road.oneway and road.width >= CENTRE_LINE_WIDTH:
        return 2
    return 0


def road_markings(roads: list[MarkedRoad]) -> RoadMarkings:
    """The markings of `roads` (see :class:`RoadMarkings`)."""
    rows_of: list[tuple[float, ...]] = []
    owners: list[int] = []
    carriageways = []
    for road in roads:
        points = np.asarray(road.centerline, dtype=np.float64)
        if len(points) < 2 or road.width <= 0.0:
            continue
        lanes = float(_lanes(road))
        edges = 1.0 if road.highway in EDGE_LINE_ROADS and road.width >= 6.0 else 0.0
        start = 0.0
        for a, b in pairwise(points):
            length = float(np.hypot(*(b - a)))
            if length < 1e-6:
                continue
            d = (b - a) / length
            rows_of.append((a[0], a[1], d[0], d[1], length, start, road.width, lanes, edges))
            owners.append(len(carriageways))
            start += length
        carriageways.append(LineString(points).buffer(0.5 * road.width, cap_style="flat"))
    if not rows_of:
        return RoadMarkings(np.zeros(2), np.full((1, 1), -1, np.int32), np.zeros((0, 9)))
    segments = np.asarray(rows_of, dtype=np.float64)
    segment_road = np.asarray(owners)
    lo = np.min([c.bounds[:2] for c in carriageways], axis=0)
    hi = np.max([c.bounds[2:] for c in carriageways], axis=0)
    origin = np.floor(lo / MARKING_CELL) * MARKING_CELL
    cols, rows = (np.ceil((hi - origin) / MARKING_CELL).astype(int) + 1).tolist()
    covered = np.zeros((rows, cols), dtype=np.int16)
    owner = np.full((rows, cols), -1, dtype=np.int32)
    for road, carriageway in enumerate(carriageways):
        window, mask = _rasterize(carriageway, origin, (rows, cols))
        covered[window] += mask
        owner[window][mask] = road
    raster = np.full((rows, cols), -1, dtype=np.int32)
    single = covered == 1
    for road in np.unique(owner[single]):
        r, c = np.nonzero(single & (owner == road))
        x = origin[0] + (c + 0.5) * MARKING_CELL
        y = origin[1] + (r + 0.5) * MARKING_CELL
        mine = np.flatnonzero(segment_road == road)
        seg = segments[mine]
        along = np.clip(
            (x[:, None] - seg[:, 0]) * seg[:, 2] + (y[:, None] - seg[:, 1]) * seg[:, 3], 0.0, seg[:, 4]
        )
        dx = x[:, None] - (seg[:, 0] + along * seg[:, 2])
        dy = y[:, None] - (seg[:, 1] + along * seg[:, 3])
        raster[r, c] = mine[np.argmin(dx * dx + dy * dy, axis=1)]
    return RoadMarkings(origin=origin, raster=raster, segments=segments)
