"""Geometry of OSM features in the local frame: lines and polygons clipped to the window, repaired.

Lines are clipped segment by segment (Liang–Barsky), so each piece keeps the way's direction (left
and right of a road stay as tagged) and a closed way stays one piece when it is wholly inside.
Polygons are made valid (``shapely.make_valid``, keeping the polygonal part), clipped with shapely
and snapped to a 1 mm grid. Output coordinates are rounded to the millimetre, so the same input gives
the same numbers. Everything that cannot be kept is counted in a ``dropped`` counter by reason.
"""

from __future__ import annotations

import itertools
import math
from collections import Counter
from collections.abc import Iterable

import numpy as np
import shapely
from shapely.geometry import LineString, MultiPolygon, Polygon, box
from shapely.geometry.base import BaseGeometry
from shapely.geometry.polygon import orient

from navverse.city.clipping import Rect, clip_segment
from navverse.city.map import Path2, Polygon2
from navverse.city.precision import GRID

__all__ = [
    "DEGENERATE",
    "GRID",
    "MIN_LINE_LENGTH",
    "MIN_POLYGON_AREA",
    "Rect",
    "as_line",
    "clip_line_pieces",
    "clip_polygon",
    "clip_polyline",
    "line_runs",
    "path2",
    "polygon2",
    "polygon_of",
    "repaired",
    "ring_polygon",
]

MIN_LINE_LENGTH = 0.1
"""Shorter line pieces are degenerate (m)."""
MIN_POLYGON_AREA = 0.5
"""Smaller polygon parts are degenerate (m²)."""

DEGENERATE = "degenerate geometry (after clipping or repair)"


def clip_polyline(points: np.ndarray, rect: Rect) -> list[np.ndarray]:
    """The pieces of a polyline inside ``rect``, each in the polyline's direction.

    Parameters
    ----------
    points : (n, 2) array
        Finite points, n >= 2.
    rect : (min_x, min_y, max_x, max_y)
        The window.

    Returns
    -------
    list of (m, 2) arrays
        Pieces of at least two points (possibly coincident: the caller drops short pieces).
    """
    pieces: list[np.ndarray] = []
    current: list[np.ndarray] = []
    for a, b in itertools.pairwise(points):
        span = clip_segment(a, b, rect)
        if span is None:
            if current:
                pieces.append(np.array(current))
            current = []
            continue
        t0, t1 = span
        start = a if t0 == 0.0 else a + t0 * (b - a)
        end = b if t1 == 1.0 else a + t1 * (b - a)
        if current and t0 == 0.0:
            current.append(end)
        else:
            if current:
                pieces.append(np.array(current))
            current = [start, end]
        if t1 != 1.0:
            pieces.append(np.array(current))
            current = []
    if current:
        pieces.append(np.array(current))
    return pieces


def line_runs(xy: np.ndarray) -> list[np.ndarray]:
    """Runs of consecutive finite rows (NaN rows are missing nodes), repeated points removed."""
    runs: list[np.ndarray] = []
    finite = np.isfinite(xy).all(axis=1)
    start = None
    for i, ok in enumerate([*finite, False]):
        if ok and start is None:
            start = i
        elif not ok and start is not None:
            run = xy[start:i]
            keep = np.ones(len(run), dtype=bool)
            keep[1:] = np.any(run[1:] != run[:-1], axis=1)
            runs.append(run[keep])
            start = None
    return runs


def _rounded(coords: Iterable[Iterable[float]]) -> list[tuple[float, float]]:
    """Points rounded to :data:`GRID`, consecutive repeats removed."""
    out: list[tuple[float, float]] = []
    for x, y in coords:
        point = (round(float(x), 3) + 0.0, round(float(y), 3) + 0.0)
        if not out or out[-1] != point:
            out.append(point)
    return out


def path2(points: np.ndarray) -> Path2 | None:
    """A :class:`Path2` of rounded points, or None if it is shorter than :data:`MIN_LINE_LENGTH`."""
    rounded = _rounded(points)
    if len(rounded) < 2:
        return None
    length = sum(math.dist(a, b) for a, b in itertools.pairwise(rounded))
    if length < MIN_LINE_LENGTH:
        return None
    return Path2(points=rounded)


def _open_ring(coords: Iterable[Iterable[float]]) -> list[tuple[float, float]] | None:
    ring = _rounded(coords)
    while len(ring) > 1 and ring[0] == ring[-1]:
        ring.pop()
    return ring if len(set(ring)) >= 3 else None


def polygon2(polygon: Polygon) -> Polygon2 | None:
    """A :class:`Polygon2` (exterior counter-clockwise, holes clockwise, rings open), or None."""
    polygon = orient(polygon, sign=1.0)
    exterior = _open_ring(polygon.exterior.coords)
    if exterior is None:
        return None
    holes = [hole for ring in polygon.interiors if (hole := _open_ring(ring.coords)) is not None]
    return Polygon2(exterior=exterior, holes=holes)


def _polygons(geometry: BaseGeometry) -> list[Polygon]:
    """The polygons in a geometry (collections flattened; lines and points left out)."""
    if isinstance(geometry, Polygon):
        return [] if geometry.is_empty else [geometry]
    if isinstance(geometry, MultiPolygon) or hasattr(geometry, "geoms"):
        return [p for part in geometry.geoms for p in _polygons(part)]
    return []


def repaired(geometry: BaseGeometry, dropped: Counter[str]) -> BaseGeometry | None:
    """A valid polygonal geometry: ``geometry`` itself, or its ``make_valid`` polygonal part (counted)."""
    if geometry.is_valid:
        return geometry
    parts = _polygons(shapely.make_valid(geometry))
    if not parts:
        dropped["invalid polygon with no area left (dropped)"] += 1
        return None
    dropped["invalid polygon (self-intersecting or overlapping rings; repaired)"] += 1
    return shapely.union_all(parts) if len(parts) > 1 else parts[0]


def ring_polygon(xy: np.ndarray, inners: Iterable[np.ndarray] = ()) -> Polygon | None:
    """A polygon from a ring's finite points (and inner rings), or None with fewer than 3 points."""
    ring = [tuple(p) for p in xy if np.isfinite(p).all()]
    if len(set(ring)) < 3:
        return None
    holes = [[tuple(p) for p in inner] for inner in inners if len({tuple(p) for p in inner}) >= 3]
    return Polygon(ring, holes)


def clip_polygon(geometry: BaseGeometry, rect: Rect, dropped: Counter[str]) -> list[Polygon]:
    """The parts of a valid polygonal geometry inside ``rect``, on the 1 mm grid, largest first.

    A geometry that misses the window (or only touches its edge) gives no parts and is not
    counted; parts under :data:`MIN_POLYGON_AREA` are counted as degenerate.
    """
    window = box(*rect)
    if not geometry.intersects(window):
        return []
    clipped = shapely.set_precision(shapely.intersection(geometry, window), GRID)
    parts = []
    for part in _polygons(clipped):
        if part.area < MIN_POLYGON_AREA:
            dropped[DEGENERATE] += 1
        else:
            parts.append(part)
    parts.sort(key=lambda p: (-round(p.area, 6), p.bounds))
    return parts


def clip_line_pieces(xy: np.ndarray, rect: Rect, dropped: Counter[str]) -> list[Path2]:
    """The window's pieces of a way's line (runs between missing nodes, clipped, rounded)."""
    runs = line_runs(xy)
    if not np.isfinite(xy).all():
        usable = any(len(run) >= 2 for run in runs)
        reason = "kept the parts between them" if usable else "too few nodes left; dropped"
        dropped[f"way with missing nodes ({reason})"] += 1
    paths = []
    for run in runs:
        if len(run) < 2:
            continue
        for piece in clip_polyline(run, rect):
            path = path2(piece)
            if path is None:
                dropped[DEGENERATE] += 1
            else:
                paths.append(path)
    return paths


def as_line(path: Path2) -> LineString:
    """A shapely line of a path."""
    return LineString(path.points)


def polygon_of(shape: Polygon2) -> Polygon:
    """A shapely polygon of a map polygon (exterior and holes)."""
    return Polygon(shape.exterior, shape.holes)
