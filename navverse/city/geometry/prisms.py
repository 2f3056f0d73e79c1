"""Solids from 2-D polygons: a triangulated top at heights given per point, vertical walls, a flat bottom.

Every 3-D part of a city is one of these: a curb strip, a stretch of sidewalk, a crosswalk ramp, a
building. Tops are triangulated with shapely's constrained Delaunay triangulation (GEOS), which keeps
the polygon's own vertices (manifold3d's ear clipping, on the same vertices, where GEOS gives up), so
a wall shares the top's vertices along each ring and a closed prism is watertight.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.base import BaseGeometry

from navverse.scene.geometry import MeshData

__all__ = ["HeightFn", "polygon_prism", "polygons_of", "triangulate"]

HeightFn = Callable[[np.ndarray], np.ndarray]
"""Heights (m) of an ``(N, 2)`` array of xy points, as an ``(N,)`` array."""


def polygons_of(geometry: BaseGeometry) -> list[Polygon]:
    """The non-empty polygons of a polygon, multipolygon or collection (lines and points left out)."""
    if geometry.is_empty:
        return []
    if isinstance(geometry, Polygon):
        return [geometry]
    if isinstance(geometry, MultiPolygon):
        return [p for p in geometry.geoms if not p.is_empty]
    return [p for g in getattr(geometry, "geoms", []) for p in polygons_of(g)]


def triangulate(polygon: Polygon) -> tuple[np.ndarray, np.ndarray]:
    """Triangles covering ``polygon`` (holes left open), on its own vertices.

    Returns
    -------
    points : ndarray, shape (N, 2)
        The distinct vertices.
    triangles : ndarray, shape (M, 3)
        Indices into ``points``, counter-clockwise seen from +z.
    """
    try:
        triangles = shapely.get_parts(shapely.constrained_delaunay_triangles(polygon))
    except shapely.errors.GEOSException:  # a valid polygon GEOS cannot triangulate (sliver holes)
        corners = _ear_clipped(polygon)
    else:
        if len(triangles) == 0:
            return np.zeros((0, 2)), np.zeros((0, 3), dtype=np.int64)
        rings = shapely.get_coordinates(shapely.get_exterior_ring(triangles))
        corners = rings.reshape(len(triangles), 4, 2)[:, :3]
    if len(corners) == 0:
        return np.zeros((0, 2)), np.zeros((0, 3), dtype=np.int64)
    points, inverse = np.unique(corners.reshape(-1, 2), axis=0, return_inverse=True)
    faces = inverse.reshape(-1, 3).astype(np.int64)
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    clockwise = cross < 0
    faces[clockwise] = faces[clockwise][:, [0, 2, 1]]
    return points, faces[cross != 0]


def _ear_clipped(polygon: Polygon) -> np.ndarray:
    """Triangle corners ``(M, 3, 2)`` of ``polygon`` by manifold3d's ear clipping, on its own vertices."""
    import manifold3d

    oriented = shapely.orient_polygons(polygon)
    rings = [
        np.asarray(ring.coords, dtype=np.float64)[:-1] for ring in (oriented.exterior, *oriented.interiors)
    ]
    triangles = np.asarray(manifold3d.triangulate(rings), dtype=np.int64).reshape(-1, 3)
    return np.concatenate(rings)[triangles]


def _ring_edges(polygon: Polygon, points: np.ndarray) -> np.ndarray:
    """Index pairs (a, b) of every ring edge, oriented so that the polygon lies left of a -> b."""
    oriented = shapely.orient_polygons(polygon)
    lookup = {(float(x), float(y)): i for i, (x, y) in enumerate(points)}
    edges: list[tuple[int, int]] = []
    for ring in (oriented.exterior, *oriented.interiors):
        coords = np.asarray(ring.coords)[:-1]
        indices = [lookup.get((float(x), float(y))) for x, y in coords]
        if any(i is None for i in indices):  # a ring vertex the triangulation left out (a spike)
            indices = [i for i in indices if i is not None]
        edges += [(a, b) for a, b in zip(indices, indices[1:] + indices[:1], strict=True) if a != b]
    return np.asarray(edges, dtype=np.int64).reshape(-1, 2)


def polygon_prism(polygon: Polygon, *, top: HeightFn, bottom: float, closed: bool = True) -> MeshData:
    """A prism over ``polygon``: the top at ``top(xy)``, vertical walls down to ``bottom``.

    Parameters
    ----------
    polygon : Polygon
        Its footprint (holes become inner walls).
    top : callable
        Heights of the top at the polygon's vertices (the top is flat within each triangle).
    bottom : float
        Height of the bottom (m), below every top height.
    closed : bool
        Whether to add the bottom face (a watertight solid); ground pieces leave it out.

    Returns
    -------
    MeshData
        Faces counter-clockwise seen from outside; empty if the polygon has no area.
    """
    points, faces = triangulate(polygon)
    if len(faces) == 0:
        return MeshData(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
    n = len(points)
    heights = np.asarray(top(points), dtype=np.float64)
    upper = np.column_stack([points, heights])
    lower = np.column_stack([points, np.full(n, float(bottom))])
    edges = _ring_edges(polygon, points)
    a, b = edges[:, 0], edges[:, 1]
    # Walls: outward is right of a -> b, so (a_low, b_low, b_up) and (a_low, b_up, a_up).
    walls = np.concatenate([np.column_stack([a + n, b + n, b]), np.column_stack([a + n, b, a])])
    parts = [faces, walls]
    if closed:
        parts.append(faces[:, ::-1] + n)
    return MeshData(np.vstack([upper, lower]), np.vstack(parts))
