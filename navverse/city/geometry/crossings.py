"""Crosswalks across the arms of junctions, for maps whose crossings are not (all) mapped.

A junction is a point where road centre lines meet with at least three arms (OSM ways share the
node; a way passing through counts twice). On every arm of a road with a sidewalk, a crosswalk is
placed just beyond the junction's corner — half the widest other carriageway there, plus its widest
sidewalk, plus :data:`CORNER_GAP`, plus half the crosswalk — unless the arm is too short for it or a
crossing of that road is already within one crosswalk width and a half. Motorways get none.
"""

from __future__ import annotations

import itertools
import re
from collections import defaultdict

from shapely.geometry import LineString, Point

from navverse.city.map import CityMap, Crossing, Road

__all__ = ["CORNER_GAP", "junction_crossings"]

CORNER_GAP = 1.0
"""Gap between a junction's corner (the far sidewalk's edge) and the crosswalk's near edge (m)."""
_NO_CROSSINGS = frozenset({"motorway", "motorway_link"})


def _key(point: tuple[float, float]) -> tuple[int, int]:
    return round(point[0] * 1000.0), round(point[1] * 1000.0)


def _arms(roads: list[Road]) -> dict[tuple[int, int], list[tuple[Road, list[tuple[float, float]]]]]:
    """For each vertex, the arms leaving it: (road, points from the vertex outwards)."""
    arms: dict[tuple[int, int], list[tuple[Road, list[tuple[float, float]]]]] = defaultdict(list)
    for road in roads:
        points = list(road.centerline.points)
        for i, point in enumerate(points):
            if i > 0:
                arms[_key(point)].append((road, points[i::-1]))
            if i < len(points) - 1:
                arms[_key(point)].append((road, points[i:]))
    return arms


def _reach(road: Road) -> float:
    """How far a road's far edge (carriageway and widest sidewalk) is from its centre line."""
    return road.reach()


def junction_crossings(city: CityMap, *, crosswalk_width: float) -> list[Crossing]:
    """Crossings to add on the junction arms of ``city`` (see the module docstring).

    Parameters
    ----------
    city : CityMap
        The map; its own crossings are kept and not repeated.
    crosswalk_width : float
        Width of a crosswalk along its road (m).

    Returns
    -------
    list of Crossing
        New crossings (kerb ``lowered``), numbered after the map's, in a fixed order.
    """
    numbers = [int(m.group(1)) for c in city.crossings if (m := re.search(r"-(\d+)$", c.id))]
    next_number = itertools.count(max(numbers, default=0) + 1)
    taken: dict[str, list[Point]] = defaultdict(list)
    for crossing in city.crossings:
        taken[crossing.road].append(Point(crossing.position))
    added: list[Crossing] = []
    for _, arms in sorted(_arms(city.roads).items()):
        if len(arms) < 3:
            continue
        for road, points in arms:
            if road.highway in _NO_CROSSINGS or (road.sidewalk_left is None and road.sidewalk_right is None):
                continue
            others = [_reach(other) for other, _ in arms if other.id != road.id]
            distance = max(others, default=0.0) + CORNER_GAP + crosswalk_width / 2.0
            line = LineString(points)
            if line.length < distance + crosswalk_width:
                continue
            position = line.interpolate(distance)
            if any(position.distance(p) < 1.5 * crosswalk_width for p in taken[road.id]):
                continue
            taken[road.id].append(position)
            added.append(
                Crossing(
                    id=f"crossing-{next(next_number)}",
                    position=(round(position.x, 3), round(position.y, 3)),
                    road=road.id,
                )
            )
    return added
