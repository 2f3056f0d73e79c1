"""The ground plan of a city: which surface class covers each point of the window, in 2-D.

:func:`plan_surfaces` turns a :class:`~navverse.city.map.CityMap` into disjoint polygons, one
(multi)polygon per class, that together tile the window exactly:

- ``road``: carriageways, each centre line buffered by half its width (round joins and ends, so
  junctions are filled without slivers), all unioned;
- ``shared``: the carriageways of :data:`SHARED_SURFACE_HIGHWAYS` (living streets, service roads,
  tracks), which have no curbs: the geometry keeps them level with the ground;
- ``crosswalk``: where a crossing is, a strip ``crosswalk_width`` wide across the road it names
  (perpendicular to the road at that point), and mapped ``footway=crossing`` ways over a road;
- ``curb``: the ``curb_width`` top strip along every road edge that borders a walked surface;
  ``lowered_curb`` where that strip meets a crosswalk (the geometry stage lowers it);
- ``sidewalk``: the strips beside roads (each side its width, from the map) and mapped walkways;
- ``building``: footprints of what stands on the ground (courtyards are holes, and the ground under
  a part raised over a passage or an overhang is not the building's, so they get the class beneath);
- ``rail``, ``water``, ``parking``, ``plaza``, ``pedestrian``, ``green``: land areas (``rail``: railway
  track beds, which roads and walkways cross at level crossings);
- ``ground``: whatever is left.

Overlaps are settled by :data:`PRIORITY` (a building wins over the sidewalk at its facade, a road
over the park it crosses). Everything is clipped to the window. Every overlay is made on the 1 mm grid
of :mod:`navverse.city.precision`, so nearly-degenerate shapes of real maps cannot break the plan.
"""

from __future__ import annotations

import math

import shapely
from shapely.geometry import LineString, Polygon, box
from shapely.geometry.base import BaseGeometry

from navverse.city.map import CityMap, Polygon2, Road
from navverse.city.precision import difference, intersection, snapped, union, union_of

__all__ = [
    "CROSSWALK_WIDTH",
    "CURB_WIDTH",
    "PRIORITY",
    "QUAD_SEGMENTS",
    "SHARED_SURFACE_HIGHWAYS",
    "SURFACE_CLASSES",
    "carriageways",
    "crosswalk_polygons",
    "plan_surfaces",
]

CURB_WIDTH = 0.15
"""Width of the curb's top strip (m)."""
CROSSWALK_WIDTH = 4.0
"""Width of a crosswalk along the road (m); crosswalks are 3–5 m wide."""
QUAD_SEGMENTS = 4
"""Segments per quarter circle of round joins and ends (a junction corner is 4 segments)."""
SHARED_SURFACE_HIGHWAYS = frozenset({"living_street", "service", "track"})
"""Road classes without curbs (shared surfaces, driveways, farm tracks): level with the ground."""
PRIORITY = (
    "building",
    "crosswalk",
    "road",
    "shared",
    "lowered_curb",
    "curb",
    "sidewalk",
    "rail",
    "water",
    "parking",
    "plaza",
    "pedestrian",
    "green",
)
"""Surface classes from the one that wins an overlap to the one that loses; ``ground`` fills the rest."""
SURFACE_CLASSES = (*PRIORITY, "ground")
"""Every class :func:`plan_surfaces` returns."""


def _polygon(shape: Polygon2) -> BaseGeometry:
    return snapped(Polygon(shape.exterior, shape.holes))


def _carriageway(road: Road) -> BaseGeometry:
    return LineString(road.centerline.points).buffer(
        road.width / 2.0, join_style="round", quad_segs=QUAD_SEGMENTS
    )


def carriageways(city: CityMap) -> dict[str, BaseGeometry]:
    """Each road's carriageway polygon, by road id."""
    return {road.id: _carriageway(road) for road in city.roads}


def _sidewalk_strips(road: Road) -> list[BaseGeometry]:
    """The strips beside a road, each side's cycle track and sidewalk beyond the carriageway edge."""
    line = LineString(road.centerline.points)
    strips = []
    for width, track, sign in (
        (road.sidewalk_left, road.cycle_track_left, 1.0),
        (road.sidewalk_right, road.cycle_track_right, -1.0),
    ):
        if width is None and track is None:
            continue
        outer = line.buffer(
            sign * (road.sidewalk_edge(sign) + (width or 0.0)),
            single_sided=True,
            join_style="round",
            quad_segs=QUAD_SEGMENTS,
        )
        strips.append(outer)
    return strips


def _crosswalk(road: Road, position: tuple[float, float], width: float) -> BaseGeometry:
    """A strip ``width`` wide along ``road`` at ``position``, spanning the carriageway and its curbs."""
    line = LineString(road.centerline.points)
    along = line.project(shapely.Point(position))
    before = line.interpolate(max(0.0, along - 0.5))
    after = line.interpolate(min(line.length, along + 0.5))
    dx, dy = after.x - before.x, after.y - before.y
    norm = math.hypot(dx, dy) or 1.0
    ux, uy = dx / norm, dy / norm
    centre = line.interpolate(along)
    half_along, half_across = width / 2.0, road.width / 2.0 + 2.0 * CURB_WIDTH
    corners = [
        (
            centre.x + sa * half_along * ux - sc * half_across * uy,
            centre.y + sa * half_along * uy + sc * half_across * ux,
        )
        for sa, sc in ((-1, -1), (1, -1), (1, 1), (-1, 1))
    ]
    return Polygon(corners)


def crosswalk_polygons(city: CityMap, *, crosswalk_width: float) -> list[tuple[str, BaseGeometry]]:
    """Each crosswalk's polygon (spanning the carriageway and its curbs) with its kerb.

    Returns
    -------
    list of (kerb, polygon)
        One per crossing node (its ``kerb``) and per mapped ``footway=crossing`` way (the kerb of a
        crossing node on it, else ``lowered``).
    """
    roads = {road.id: road for road in city.roads}
    found: list[tuple[str, BaseGeometry]] = [
        (c.kerb, _crosswalk(roads[c.road], c.position, crosswalk_width)) for c in city.crossings
    ]
    for walkway in city.walkways:
        if walkway.kind != "crossing":
            continue
        polygon = LineString(walkway.centerline.points).buffer(walkway.width / 2.0, cap_style="flat")
        kerbs = [c.kerb for c in city.crossings if polygon.distance(shapely.Point(c.position)) < 0.5]
        found.append((kerbs[0] if kerbs else "lowered", polygon))
    return found


def plan_surfaces(city: CityMap, *, curb_width: float, crosswalk_width: float) -> dict[str, BaseGeometry]:
    """Disjoint (multi)polygons per surface class that tile the city's window.

    Parameters
    ----------
    city : CityMap
        The map.
    curb_width : float
        Width of the curb top strip along road edges (m).
    crosswalk_width : float
        Width of a crosswalk along the road (m).

    Returns
    -------
    dict
        ``{class: geometry}`` for every class of :data:`SURFACE_CLASSES` (empty geometries
        included), pairwise disjoint (up to shared edges), covering the window.
    """
    window = box(*city.window)
    lanes = carriageways(city)
    kinds = {road.id: road.highway in SHARED_SURFACE_HIGHWAYS for road in city.roads}
    road_area = union_of(p for road_id, p in lanes.items() if not kinds[road_id])
    shared_area = union_of(p for road_id, p in lanes.items() if kinds[road_id])
    walkway_area = union_of(
        LineString(w.centerline.points).buffer(w.width / 2.0, join_style="round", quad_segs=QUAD_SEGMENTS)
        for w in city.walkways
        if w.kind != "crossing"
    )
    crosswalks = union_of(p for _, p in crosswalk_polygons(city, crosswalk_width=crosswalk_width))
    sidewalk_area = union_of([*(s for road in city.roads for s in _sidewalk_strips(road)), walkway_area])
    walked = union(sidewalk_area, crosswalks)
    edge_strip = difference(road_area.buffer(curb_width, join_style="mitre"), road_area)
    curb = intersection(edge_strip, walked)
    lowered = intersection(curb, crosswalks)
    by_class: dict[str, BaseGeometry] = {
        "building": union_of(_polygon(b.footprint) for b in city.buildings if b.base_height == 0.0),
        "crosswalk": intersection(crosswalks, road_area),
        "road": road_area,
        "shared": shared_area,
        "lowered_curb": lowered,
        "curb": curb,
        "sidewalk": sidewalk_area,
    }
    for cls in ("rail", "water", "parking", "plaza", "pedestrian", "green"):
        by_class[cls] = union_of(_polygon(a.polygon) for a in city.areas if a.cls == cls)
    taken: BaseGeometry = Polygon()
    plan: dict[str, BaseGeometry] = {}
    for cls in PRIORITY:
        inside = by_class[cls]
        if not window.contains(inside.envelope):
            inside = intersection(inside, window)
        own = difference(inside, taken)
        plan[cls] = own
        if not own.is_empty:
            taken = union(taken, own)
    plan["ground"] = difference(window, taken)
    return plan
