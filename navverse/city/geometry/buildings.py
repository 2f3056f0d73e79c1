"""Buildings of a city map as closed solids, with their scene annotations (format 2.2).

Each footprint (courtyards as holes) is extruded from its base (``base_height`` above the lowest
terrain under it) to its height, a watertight prism of terrain class ``building``; its floor and roof
are level. On a sloping terrain a building standing on the ground reaches :data:`PLINTH_DEPTH`
below its base (a plinth in the ground; on a relief, the lowest terrain is looked for over and
inside the footprint), so its level floor meets the ground at its lowest point and the rising
ground covers the foot of its walls elsewhere, with no gap under them. Its annotation
lists the facades: runs of the outline's edges that turn by less than :data:`FACADE_TURN_DEG`,
each with its base segment, outward normal and height, and — when the first thing its normal meets
from the segment's middle within :data:`FACING_RANGE` is a carriageway — the road it faces and how
far. Courtyard walls are facades too (their normals point into the courtyard). ``entrance=*`` nodes
become exits on the nearest facade, :data:`ENTRANCE_WIDTH` wide.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry

from navverse.city.geometry.prisms import HeightFn, polygon_prism, polygons_of
from navverse.city.map import Building, CityMap
from navverse.scene.annotations import BuildingAnnotation, ExitAnnotation, FacadeAnnotation
from navverse.scene.geometry import MeshData, Surface

__all__ = [
    "ENTRANCE_WIDTH",
    "FACADE_TURN_DEG",
    "FACING_RANGE",
    "GROUND_SPACING",
    "MIN_FACADE",
    "PLINTH_DEPTH",
    "building_parts",
]

FACADE_TURN_DEG = 10.0
"""Consecutive outline edges turning by less than this (degrees) belong to one facade."""
MIN_FACADE = 0.5
"""Facades shorter than this (m) are not listed (their wall is still built)."""
FACING_RANGE = 50.0
"""How far a facade looks for the road it faces (m)."""
ENTRANCE_WIDTH = 1.2
"""Width given to an ``entrance=*`` node's doorway (m)."""
GROUND_SPACING = 0.5
"""On a curved terrain, how far apart the points are at which the lowest ground under a footprint is
looked for (m), over and inside it."""
PLINTH_DEPTH = 0.5
"""On a sloping terrain, how far below its base (the lowest ground under it) a building standing on
the ground reaches (m), so that no chord of a draped ground passes under its walls."""


def _polygon(building: Building) -> BaseGeometry:
    polygon = Polygon(building.footprint.exterior, building.footprint.holes)
    return polygon if polygon.is_valid else shapely.make_valid(polygon)


def _runs(ring: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Straight runs of a closed ring (open coordinates, interior on the left): (start, end) pairs."""
    n = len(ring)
    direction = np.roll(ring, -1, axis=0) - ring
    lengths = np.hypot(direction[:, 0], direction[:, 1])
    keep = lengths > 1e-9
    ring, direction = ring[keep], direction[keep]
    n = len(ring)
    if n < 3:
        return []
    heading = np.arctan2(direction[:, 1], direction[:, 0])
    turn = np.abs((np.diff(heading, append=heading[:1]) + math.pi) % (2 * math.pi) - math.pi)
    breaks = np.flatnonzero(turn >= math.radians(FACADE_TURN_DEG))  # a corner after edge i
    if len(breaks) == 0:
        breaks = np.array([n - 1])
    runs = []
    for first, last in zip(breaks, np.roll(breaks, -1), strict=True):
        start = (first + 1) % n
        end = (last + 1) % n  # the run's edges are start .. last, ending at vertex last + 1
        runs.append((ring[start], ring[end]))
    return runs


def _facing(
    middle: np.ndarray,
    normal: np.ndarray,
    *,
    roads: shapely.STRtree,
    road_ids: list[str],
    road_shapes: list[BaseGeometry],
    blockers: shapely.STRtree,
    blocker_shapes: list[BaseGeometry],
    own: int,
) -> tuple[str, float] | None:
    """The road a facade's normal meets first (within :data:`FACING_RANGE`), and how far."""
    start = middle + normal * 0.01
    ray = LineString([start, start + normal * FACING_RANGE])
    origin = Point(start)
    nearest: tuple[float, str | None] = (math.inf, None)
    for index in roads.query(ray, predicate="intersects"):
        distance = origin.distance(ray.intersection(road_shapes[index]))
        if distance < nearest[0]:
            nearest = (distance, road_ids[index])
    if nearest[1] is None:
        return None
    for index in blockers.query(ray, predicate="intersects"):
        if index != own and origin.distance(ray.intersection(blocker_shapes[index])) < nearest[0]:
            return None
    return nearest[1], round(nearest[0] + 0.01, 3)


def _under(pieces: list[Polygon], spacing: float) -> np.ndarray:
    """Points under a footprint: its rings' vertices ``spacing`` apart and a grid of that spacing inside."""
    points = [shapely.get_coordinates(shapely.segmentize(piece, spacing)) for piece in pieces]
    for piece in pieces:
        x0, y0, x1, y1 = piece.bounds
        gx, gy = (g.ravel() for g in np.meshgrid(np.arange(x0, x1, spacing), np.arange(y0, y1, spacing)))
        inside = shapely.contains_xy(piece, gx, gy)
        points.append(np.column_stack([gx[inside], gy[inside]]))
    return np.concatenate(points)


def building_parts(
    city: CityMap,
    carriageways: Mapping[str, BaseGeometry],
    *,
    terrain: HeightFn,
    step: float | None = None,
    plinth: float = 0.0,
) -> tuple[list[Surface], list[BuildingAnnotation]]:
    """Solids and annotations of the city's buildings, numbered 1, 2, ... in map order.

    Parameters
    ----------
    city : CityMap
        The map.
    carriageways : mapping
        Each road's carriageway polygon by road id (:func:`~navverse.city.geometry.surfaces.carriageways`).
    terrain : callable
        Height of the terrain at xy points.
    step : float, optional
        Given for a curved terrain (a relief; the spacing the ground is draped with): the lowest
        ground under a footprint is looked for at points :data:`GROUND_SPACING` apart, over and
        inside it. None (flat or planar terrain): the lowest of the outline's corners.
    plinth : float
        How far below its base a building standing on the ground reaches (m):
        :data:`PLINTH_DEPTH` on a sloping terrain, 0 on a flat one.

    Returns
    -------
    surfaces : list of Surface
        ``building_NNNN``, class ``building``, one closed solid per building.
    annotations : list of BuildingAnnotation
        Footprint (the outline), base height, height, map id, facades and entrances.
    """
    road_ids = list(carriageways)
    road_shapes = [carriageways[r] for r in road_ids]
    roads = shapely.STRtree(road_shapes)
    shapes = [_polygon(b) for b in city.buildings]
    blockers = shapely.STRtree(shapes)
    surfaces: list[Surface] = []
    annotations: list[BuildingAnnotation] = []
    facade_id = 0
    exit_id = 0
    for index, (building, shape) in enumerate(zip(city.buildings, shapes, strict=True)):
        pieces = polygons_of(shape)
        if not pieces:
            continue
        outline = max(pieces, key=lambda p: p.area)
        if step is None:
            ground = float(terrain(np.asarray(outline.exterior.coords)).min())
        else:
            ground = float(terrain(_under(pieces, GROUND_SPACING)).min())
        base = ground + building.base_height
        top = ground + max(building.height, building.base_height + 0.5)
        bottom = base - plinth if building.base_height == 0.0 else base
        meshes = [
            polygon_prism(piece, top=lambda xy, z=top: np.full(len(xy), z), bottom=bottom, closed=True)
            for piece in pieces
        ]
        number = len(annotations) + 1
        facades: list[FacadeAnnotation] = []
        oriented = shapely.orient_polygons(outline)
        for ring in (oriented.exterior, *oriented.interiors):
            for start, end in _runs(np.asarray(ring.coords)[:-1]):
                length = float(np.hypot(*(end - start)))
                if length < MIN_FACADE:
                    continue
                along = (end - start) / length
                normal = np.array([along[1], -along[0]])
                faced = _facing(
                    (start + end) / 2.0,
                    normal,
                    roads=roads,
                    road_ids=road_ids,
                    road_shapes=road_shapes,
                    blockers=blockers,
                    blocker_shapes=shapes,
                    own=index,
                )
                facade_id += 1
                facades.append(
                    FacadeAnnotation(
                        id=facade_id,
                        segment=(
                            (round(float(start[0]), 3), round(float(start[1]), 3)),
                            (round(float(end[0]), 3), round(float(end[1]), 3)),
                        ),
                        normal=(float(normal[0]), float(normal[1])),
                        height=round(top - base, 3),
                        road=faced[0] if faced else None,
                        road_distance=faced[1] if faced else None,
                    )
                )
        exits: list[ExitAnnotation] = []
        for x, y in building.entrances:
            if not facades:
                break
            point = Point(x, y)
            facade = min(facades, key=lambda f: LineString(f.segment).distance(point))
            exit_id += 1
            exits.append(
                ExitAnnotation(
                    id=exit_id,
                    center=(float(x), float(y), base),
                    width=ENTRANCE_WIDTH,
                    facing=math.atan2(facade.normal[1], facade.normal[0]),
                    facade=facade.id,
                )
            )
        exterior = [(float(x), float(y)) for x, y in np.asarray(oriented.exterior.coords)[:-1]]
        annotations.append(
            BuildingAnnotation(
                id=number,
                footprint=exterior,
                base_height=base,
                height=round(top - base, 3),
                map_id=building.id,
                osm=building.osm,
                exits=exits,
                facades=facades,
            )
        )
        mesh = MeshData.concatenate(meshes)
        surfaces.append(Surface(name=f"building_{number:04d}", terrain_class="building", mesh=mesh))
    return surfaces, annotations
