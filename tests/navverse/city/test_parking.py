"""Parking slots: inside their bands or lots, apart from each other, aligned with the street."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Point
from shapely.strtree import STRtree

from navverse.city.geometry.scene import CityGeometry, geometry_plan
from navverse.city.street_life.parking import lot_slots, slot_polygon, street_slots
from navverse.city.street_life.zones import street_zones
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city


@pytest.fixture(scope="module")
def city():
    city = synthetic_city(SyntheticCityParams(size=(400.0, 400.0)), seed=5)
    plan = geometry_plan(city, CityGeometry(junction_crosswalks=True))
    return city, plan, street_zones(city, plan)


def _apart(polygons) -> None:
    tree = STRtree(polygons)
    for i, polygon in enumerate(polygons):
        for j in tree.query(polygon, predicate="intersects"):
            if j != i:
                assert polygon.intersection(polygons[j]).area < 1e-6


def test_street_slots_stay_in_their_bands_off_crosswalks_and_follow_the_street(city) -> None:
    city_map, plan, zones = city
    slots = street_slots(city_map, zones, np.random.default_rng(0))
    assert len(slots) > 100
    polygons = [slot_polygon(s) for s in slots]
    bands = zones.parking.union(zones.curbside).buffer(1e-6)
    crosswalks = plan.classes["crosswalk"].union(plan.classes["lowered_curb"])
    lines = [LineString(r.centerline.points) for r in city_map.roads]
    tree = STRtree(lines)
    for slot, polygon in zip(slots, polygons, strict=True):
        assert bands.contains(polygon)
        assert polygon.distance(crosswalks) >= 0.99
        line = lines[int(tree.nearest(Point(slot.x, slot.y)))]
        along = line.project(Point(slot.x, slot.y))
        a, b = line.interpolate(max(0.0, along - 1.0)), line.interpolate(min(line.length, along + 1.0))
        tangent = math.atan2(b.y - a.y, b.x - a.x)
        assert abs(math.sin(slot.heading - tangent)) < 0.05  # parallel to the street
    _apart(polygons)
    again = street_slots(city_map, zones, np.random.default_rng(0))
    assert again == slots


def test_lot_stalls_fill_parking_lots_in_rows() -> None:
    city_map = synthetic_city(SyntheticCityParams(size=(500.0, 500.0)), seed=0)
    lots = geometry_plan(city_map, CityGeometry()).classes["parking"]
    assert lots.area > 1000.0
    slots = lot_slots(lots)
    # A stall and its half of the aisle take 2.5 m x 8 m; odd shapes and edges lose some.
    assert len(slots) >= 0.5 * lots.area / (2.5 * 8.0)
    polygons = [slot_polygon(s) for s in slots]
    for polygon in polygons:
        assert lots.buffer(1e-6).contains(polygon)
    _apart([slot_polygon(s, length=5.0, width=2.5).buffer(-1e-3) for s in slots])
