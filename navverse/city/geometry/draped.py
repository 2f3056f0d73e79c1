"""Prisms whose tops follow a curved terrain: polygons cut into grid cells, edges at most a step long.

:func:`~navverse.city.geometry.prisms.polygon_prism` triangulates a top on the polygon's own
vertices, which is exact on a plane but cuts chords through hills. :func:`draped_prism` first cuts
the polygon along a world grid of :data:`DRAPE_CELL` (every polygon along the same lines, on the
1 mm grid of :mod:`navverse.city.precision`, so that neighbours share the cut points), then
splits every edge to at most :data:`DRAPE_STEP`, and triangulates each piece on those vertices.
The walls stand only on the polygon's own boundary (not on the cuts between its pieces), as
:func:`~navverse.city.geometry.prisms.polygon_prism`'s: outward, from the top down to a level foot;
a closed prism has a bottom face there too. Two neighbours' tops meet at the same heights wherever
they share vertices, and within the chord of a step elsewhere.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry

from navverse.city.geometry.prisms import HeightFn, polygons_of, triangulate
from navverse.city.precision import intersection
from navverse.scene.geometry import MeshData

__all__ = ["DRAPE_CELL", "DRAPE_STEP", "draped_prism", "grid_pieces"]

DRAPE_STEP = 3.0
"""Longest edge of a draped polygon's boundary (m): on hills graded to the road limits the chord of
a 3 m step sags by a few millimetres, and neighbours sharing their vertices meet exactly."""
DRAPE_CELL = 16.0
"""Side of the world grid cells that draped polygons are cut along (m), so that their tops get
vertices inside too."""
_OUTWARD = 5e-3
"""How far beside the middle of an edge on a grid line the polygon is probed to tell a cut (the
polygon on both sides) from its own boundary (m)."""


def grid_pieces(polygon: Polygon, cell: float = DRAPE_CELL) -> list[Polygon]:
    """``polygon`` cut along the world grid lines ``x = k * cell`` and ``y = k * cell``, in a fixed order.

    Halves are cut at the grid line nearest the middle, recursively, so the work grows with the
    polygon's vertices times the depth, not with the number of cells.
    """
    pieces: list[Polygon] = []
    stack: list[BaseGeometry] = [polygon]
    while stack:
        shape = stack.pop()
        x0, y0, x1, y1 = shape.bounds
        cut = _cut(x0, x1, cell)
        if cut is not None:
            halves = (box(x0 - 1.0, y0 - 1.0, cut, y1 + 1.0), box(cut, y0 - 1.0, x1 + 1.0, y1 + 1.0))
        else:
            cut = _cut(y0, y1, cell)
            if cut is None:
                pieces.extend(polygons_of(shape))
                continue
            halves = (box(x0 - 1.0, y0 - 1.0, x1 + 1.0, cut), box(x0 - 1.0, cut, x1 + 1.0, y1 + 1.0))
        for half in reversed(halves):
            part = intersection(shape, half)
            if not part.is_empty:
                stack.append(part)
    return pieces


def _cut(low: float, high: float, cell: float) -> float | None:
    """The grid line strictly inside (low, high) nearest its middle, or None."""
    first, last = math.floor(low / cell) + 1, math.ceil(high / cell) - 1
    if first > last:
        return None
    middle = min(max(round((low + high) / 2.0 / cell), first), last)
    return middle * cell


def _on_grid_line(a: np.ndarray, b: np.ndarray, cell: float) -> np.ndarray:
    """Whether each edge a -> b lies on one of the grid's lines (both ends on it)."""
    found = np.zeros(len(a), dtype=bool)
    for axis in (0, 1):
        line = np.round(a[:, axis] / cell) * cell
        found |= (np.abs(a[:, axis] - line) < 1e-6) & (np.abs(b[:, axis] - line) < 1e-6)
    return found


def draped_prism(
    polygon: Polygon,
    *,
    top: HeightFn,
    depth: float,
    closed: bool = False,
    step: float = DRAPE_STEP,
    cell: float = DRAPE_CELL,
) -> MeshData:
    """A prism over ``polygon`` whose top follows ``top`` at vertices at most ``step`` apart.

    Parameters
    ----------
    polygon : Polygon
        Its footprint (holes become inner walls).
    top : callable
        Heights of the top at xy points.
    depth : float
        How far below the lowest top vertex the walls reach: the prism's foot (m).
    closed : bool
        Whether to add a bottom face at the foot (under each piece), so that the prism is a closed
        solid for the navmesh's filling of solids; ground pieces leave it out.
    step, cell : float
        Longest boundary edge and grid cell (m).

    Returns
    -------
    MeshData
        Tops counter-clockwise seen from above, walls and bottom outward; empty if the polygon has
        no area.
    """
    tops: list[tuple[np.ndarray, np.ndarray]] = []
    edges: list[np.ndarray] = []
    for piece in grid_pieces(polygon, cell):
        piece = shapely.orient_polygons(shapely.segmentize(piece, step))
        points, faces = triangulate(piece)
        if len(faces):
            tops.append((points, faces))
        for ring in (piece.exterior, *piece.interiors):
            coords = np.asarray(ring.coords)
            edges.append(np.concatenate([coords[:-1], coords[1:]], axis=1))
    if not tops:
        return MeshData(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
    segments = np.concatenate(edges)  # (a_x, a_y, b_x, b_y), the piece on the left of a -> b
    a, b = segments[:, :2], segments[:, 2:]
    along = b - a
    length = np.hypot(along[:, 0], along[:, 1])
    segments, a, b, along, length = (v[length > 1e-9] for v in (segments, a, b, along, length))
    right = np.column_stack([along[:, 1], -along[:, 0]]) / length[:, None]
    probe = (a + b) / 2.0 + right * _OUTWARD
    shapely.prepare(polygon)
    cut = _on_grid_line(a, b, cell) & shapely.contains_xy(polygon, probe[:, 0], probe[:, 1])
    a, b = a[~cut], b[~cut]
    vertices: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    count = 0
    for points, triangles in tops:
        vertices.append(np.column_stack([points, top(points)]))
        faces.append(triangles + count)
        count += len(points)
    foot = min(float(v[:, 2].min()) for v in vertices) - depth
    if closed:
        for points, triangles in tops:
            vertices.append(np.column_stack([points, np.full(len(points), foot)]))
            faces.append(triangles[:, ::-1] + count)
            count += len(points)
    if len(a):
        n = len(a)
        upper_a = np.column_stack([a, top(a)])
        upper_b = np.column_stack([b, top(b)])
        lower_a = np.column_stack([a, np.full(n, foot)])
        lower_b = np.column_stack([b, np.full(n, foot)])
        vertices.append(np.concatenate([upper_a, upper_b, lower_a, lower_b]))
        k = np.arange(n) + count
        ua, ub, la, lb = k, k + n, k + 2 * n, k + 3 * n
        # Outward is right of a -> b: (a_low, b_low, b_up) and (a_low, b_up, a_up), as polygon_prism's walls.
        faces.append(np.concatenate([np.column_stack([la, lb, ub]), np.column_stack([la, ub, ua])]))
    return MeshData(np.concatenate(vertices), np.concatenate(faces).astype(np.int64))
