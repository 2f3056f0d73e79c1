"""Exact Euclidean shortest paths in a flat navmesh's free space, for checking geodesic distances.

The free space is the union of the navmesh polygons (2-D); the shortest path between two points of
it bends only at reflex corners of its boundary, so Dijkstra over the visibility graph of those
corners (plus the two points) gives the exact length. Quadratic in the corners: for test scenes.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from navverse.nav import PathFinder


class ExactPaths:
    """Shortest paths in the 2-D free space of a single-level navmesh."""

    def __init__(self, finder: PathFinder, *, tolerance: float = 1e-4) -> None:
        polygons = [Polygon(p[:, :2]) for p in finder.polygons()]
        self.free = unary_union(polygons).buffer(tolerance, join_style="mitre")
        shapely.prepare(self.free)
        self.corners = _reflex_corners(self.free)
        n = len(self.corners)
        rows, cols, weights = [], [], []
        for i in range(n):
            for j in range(i + 1, n):
                if self._visible(self.corners[i], self.corners[j]):
                    d = float(np.linalg.norm(self.corners[i] - self.corners[j]))
                    rows += [i, j]
                    cols += [j, i]
                    weights += [d, d]
        self._edges = (rows, cols, weights)

    def _visible(self, a: np.ndarray, b: np.ndarray) -> bool:
        return bool(self.free.covers(LineString([a, b])))

    def distance(self, start: np.ndarray, end: np.ndarray) -> float:
        """Length of the shortest path from start to end (x, y used), inf if none."""
        a, b = np.asarray(start, float)[:2], np.asarray(end, float)[:2]
        if not (self.free.covers(Point(a)) and self.free.covers(Point(b))):
            return float("inf")
        if self._visible(a, b):
            return float(np.linalg.norm(b - a))
        n = len(self.corners)
        rows, cols, weights = (list(x) for x in self._edges)
        for index, point in ((n, a), (n + 1, b)):
            for i, corner in enumerate(self.corners):
                if self._visible(point, corner):
                    d = float(np.linalg.norm(point - corner))
                    rows += [index, i]
                    cols += [i, index]
                    weights += [d, d]
        graph = csr_matrix((weights, (rows, cols)), shape=(n + 2, n + 2))
        return float(dijkstra(graph, indices=n)[n + 1])


def _reflex_corners(free) -> np.ndarray:
    """Corners of the free space's boundary where it turns into the free space (obstacle corners)."""
    corners = []
    for polygon in getattr(free, "geoms", [free]):
        polygon = shapely.geometry.polygon.orient(polygon, sign=1.0)  # exterior CCW, holes CW
        for ring in [polygon.exterior, *polygon.interiors]:
            pts = np.asarray(ring.coords)[:-1]
            prev, nxt = np.roll(pts, 1, axis=0), np.roll(pts, -1, axis=0)
            cross = (pts[:, 0] - prev[:, 0]) * (nxt[:, 1] - pts[:, 1]) - (pts[:, 1] - prev[:, 1]) * (
                nxt[:, 0] - pts[:, 0]
            )
            corners.append(pts[cross < -1e-12])  # a right turn on a CCW exterior / CW hole: reflex
    return np.vstack(corners) if corners else np.zeros((0, 2))
