"""Sidewalk zones and parking bands of a synthetic city: they tile the sidewalks, keep the walkway
clear, and keep away from crosswalks and junctions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Point

from navverse.city.scene import CityGeometry, geometry_plan
from navverse.city.street_zones import StreetZones, ZoneSettings, street_zones
from navverse.city.synthetic import SyntheticCityParams, synthetic_city

SETTINGS = ZoneSettings()


@pytest.fixture(scope="module")
def city_and_zones():
    city = synthetic_city(SyntheticCityParams(size=(400.0, 400.0)), seed=3)
    plan = geometry_plan(city, CityGeometry(junction_crosswalks=True))
    return city, plan, street_zones(city, plan, SETTINGS)


def test_the_zones_tile_the_sidewalks_without_overlap(city_and_zones) -> None:
    _, plan, zones = city_and_zones
    sidewalk = plan.classes["sidewalk"]
    parts = (zones.furniture, zones.walkway, zones.frontage)
    assert sum(p.area for p in parts) == pytest.approx(sidewalk.area, rel=1e-6)
    for i, a in enumerate(parts):
        assert a.difference(sidewalk.buffer(1e-6)).area < 1e-6
        for b in parts[i + 1 :]:
            assert a.intersection(b).area < 1e-6
    assert zones.furniture.area > 0.05 * sidewalk.area and zones.frontage.area > 0


def test_furniture_keeps_off_crosswalks_and_corners(city_and_zones) -> None:
    _, plan, zones = city_and_zones
    crosswalks = plan.classes["crosswalk"].union(plan.classes["lowered_curb"])
    assert zones.furniture.distance(crosswalks) >= SETTINGS.crosswalk_margin - 1e-6
    assert zones.furniture.intersection(zones.junctions).area < 1e-6


def test_parking_bands_lie_on_the_road_clear_of_crossings_junctions_and_driveways(city_and_zones) -> None:
    city, plan, zones = city_and_zones
    bands = zones.curbside.union(zones.parking)
    assert bands.area > 1000.0
    assert bands.difference(plan.classes["road"].buffer(1e-6)).area < 1e-6
    crosswalks = plan.classes["crosswalk"].union(plan.classes["lowered_curb"])
    assert bands.distance(crosswalks) >= SETTINGS.crosswalk_margin - 1e-6
    assert bands.intersection(zones.junctions).area < 1e-6
    # No band on a street narrower than one parking band and a lane.
    for road in city.roads:
        if road.width < SETTINGS.curbside_min_width:
            line = LineString(road.centerline.points)
            assert bands.intersection(line.buffer(road.width / 2.0 - 0.05)).area < 1e-3


def _across(line: LineString, along: float, sign: float, start: float, end: float) -> LineString:
    here = line.interpolate(along)
    ahead = line.interpolate(min(line.length, along + 0.5))
    behind = line.interpolate(max(0.0, along - 0.5))
    dx, dy = ahead.x - behind.x, ahead.y - behind.y
    norm = math.hypot(dx, dy)
    nx, ny = -dy / norm * sign, dx / norm * sign
    return LineString([(here.x + nx * start, here.y + ny * start), (here.x + nx * end, here.y + ny * end)])


def test_the_walkway_stays_clear_across_every_sidewalk(city_and_zones) -> None:
    city, _, zones = city_and_zones
    checked = 0
    for road in city.roads:
        line = LineString(road.centerline.points)
        for sign, width in ((1.0, road.sidewalk_left), (-1.0, road.sidewalk_right)):
            if width is None:
                continue
            usable = width - SETTINGS.curb_width
            need = min(
                usable, SETTINGS.clear_width if usable - SETTINGS.clear_width >= 0.3 else SETTINGS.min_clear
            )
            for along in np.arange(2.5, line.length - 2.5, 5.0):
                cut = _across(line, along, sign, road.width / 2.0 + 0.2, road.width / 2.0 + width - 0.05)
                if cut.distance(zones.junctions) < 1.0 or not zones.walkway.intersects(Point(cut.coords[-1])):
                    continue  # corners, and where another street's sidewalk or a building takes over
                assert cut.intersection(zones.walkway).length >= need - 0.06
                checked += 1
    assert checked > 200


def test_a_narrow_sidewalk_is_all_walkway() -> None:
    city = synthetic_city(SyntheticCityParams(size=(200.0, 200.0), sidewalk=1.4), seed=1)
    plan = geometry_plan(city, CityGeometry(junction_crosswalks=True))
    zones: StreetZones = street_zones(city, plan, SETTINGS)
    residential = [r for r in city.roads if r.highway == "residential"]
    assert residential
    for road in residential:
        strip = LineString(road.centerline.points).buffer(road.width / 2.0 + 1.4)
        assert zones.furniture.intersection(strip).area < 1e-3
