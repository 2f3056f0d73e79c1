"""Polygon overlays on a fixed precision grid, so that street geometry never depends on luck.

Real maps hold nearly-degenerate shapes: ways that run a hair apart, rings that touch themselves,
buffers whose arcs almost meet. Floating-point overlays of such shapes can fail ("side location
conflict", "ring edge missing") or not, depending on a metre's shift of the window. Every overlay of
the city's ground plan goes through this module instead: GEOS's snap-rounding overlay on a
:data:`GRID` of 1 mm (the map's own rounding), which is robust by construction and returns valid
geometry. What enters the plan (a buffer, a footprint, an area) enters through :func:`union_of` or
:func:`snapped`, which put it on the grid and repair it (``make_valid``) if snapping made it invalid;
overlays of such shapes stay on the grid and valid.

The functions take and return shapely geometries; results are polygonal (lines and points an overlay
leaves behind are dropped) and empty results are an empty ``Polygon``.
"""

from __future__ import annotations

from collections.abc import Iterable

import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.base import BaseGeometry

__all__ = ["GRID", "areal", "difference", "intersection", "snapped", "union", "union_of"]

GRID = 1e-3
"""Size of the precision grid of every overlay (m): the millimetre the map's coordinates are rounded to."""


def areal(geometry: BaseGeometry | None) -> BaseGeometry:
    """The polygonal part of ``geometry`` (an overlay can leave lines and points behind)."""
    if geometry is None or geometry.is_empty:
        return Polygon()
    if isinstance(geometry, Polygon | MultiPolygon):
        return geometry
    polygonal = (Polygon, MultiPolygon)
    parts = [p for p in shapely.get_parts(geometry) if isinstance(p, polygonal) and not p.is_empty]
    if not parts:
        return Polygon()
    return parts[0] if len(parts) == 1 else shapely.union_all(parts, grid_size=GRID)


def snapped(geometry: BaseGeometry) -> BaseGeometry:
    """``geometry`` on the grid and valid: its polygonal part, repaired if snapping broke it."""
    if geometry.is_empty:
        return Polygon()
    on_grid = shapely.set_precision(geometry, GRID)
    if not on_grid.is_valid:
        on_grid = shapely.make_valid(on_grid)
    # set_precision also stores the grid in the geometry, and GEOS then rounds later operations on it
    # (a buffer by -1 µm collapses a box): keep the coordinates, drop the stored grid.
    return areal(shapely.set_precision(on_grid, 0.0))


def union_of(geometries: Iterable[BaseGeometry]) -> BaseGeometry:
    """The union of the non-empty ``geometries``, on the grid (an empty polygon if there are none).

    Many shapes are merged in floating point (valid inputs: repaired first) and the result is put on
    the grid; should GEOS fail on them, they are merged on the grid instead, which cannot fail.
    """
    items = [g if g.is_valid else shapely.make_valid(g) for g in geometries if not g.is_empty]
    if not items:
        return Polygon()
    try:
        merged = shapely.union_all(items)
    except shapely.errors.GEOSException:
        merged = shapely.union_all([snapped(g) for g in items], grid_size=GRID)
    return snapped(merged)


def union(a: BaseGeometry, b: BaseGeometry) -> BaseGeometry:
    """``a`` ∪ ``b`` on the grid."""
    if a.is_empty or b.is_empty:
        return snapped(b if a.is_empty else a)
    return areal(shapely.union(a, b, grid_size=GRID))


def intersection(a: BaseGeometry, b: BaseGeometry) -> BaseGeometry:
    """``a`` ∩ ``b`` on the grid (polygonal part)."""
    if a.is_empty or b.is_empty:
        return Polygon()
    return areal(shapely.intersection(a, b, grid_size=GRID))


def difference(a: BaseGeometry, b: BaseGeometry) -> BaseGeometry:
    """``a`` minus ``b`` on the grid (polygonal part)."""
    if a.is_empty:
        return Polygon()
    if b.is_empty:
        return snapped(a)
    return areal(shapely.difference(a, b, grid_size=GRID))
