"""Sidewalk zones and parking bands of a synthetic city: they tile the sidewalks, keep the walkway
clear, and keep away from crosswalks and junctions."""

from __future__ import annotations

import pytest
from shapely.geometry import LineString

from navverse.city.geometry.scene import CityGeometry, geometry_plan
from navverse.city.precision import GRID
from navverse.city.street_life.zones import StreetZones, ZoneSettings, street_zones, walkway_clearance
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city

SETTINGS = ZoneSettings()
# The ground plan lies on a 1 mm grid, so the zones cut from it keep their margins to within a grid step.


@pytest.fixture(scope="module")
def city_and_zones():
    city = synthetic_city(SyntheticCityParams(size=(400.0, 400.0)), seed=3)
    plan = geometry_plan(city, CityGeometry(junction_crosswalks=True))
    return city, plan, street_zones(city, plan, SETTINGS)


def _thin(shape) -> bool:
    """Whether ``shape`` is nothing thicker than the grid step (a seam the snapping leaves)."""
    return shape.buffer(-GRID).is_empty


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
    assert zones.furniture.distance(crosswalks) >= SETTINGS.crosswalk_margin - GRID
    assert _thin(zones.furniture.intersection(zones.junctions))


def test_parking_bands_lie_on_the_road_clear_of_crossings_junctions_and_driveways(city_and_zones) -> None:
    city, plan, zones = city_and_zones
    bands = zones.curbside.union(zones.parking)
    assert bands.area > 1000.0
    assert bands.difference(plan.classes["road"].buffer(1e-6)).area < 1e-6
    crosswalks = plan.classes["crosswalk"].union(plan.classes["lowered_curb"])
    assert bands.distance(crosswalks) >= SETTINGS.crosswalk_margin - GRID
    assert _thin(bands.intersection(zones.junctions))
    # No band on a street narrower than one parking band and a lane.
    for road in city.roads:
        if road.width < SETTINGS.curbside_min_width:
            line = LineString(road.centerline.points)
            assert bands.intersection(line.buffer(road.width / 2.0 - 0.05)).area < 1e-3


def test_the_walkway_stays_clear_across_every_sidewalk(city_and_zones) -> None:
    city, _, zones = city_and_zones
    widths = walkway_clearance(city, zones)
    assert len(widths) > 200
    # Every sidewalk of this city is wide enough for the least clear width: 1.3 m (1.5 m where wider).
    assert widths.min() >= SETTINGS.min_clear - 0.01
    assert widths.max() >= SETTINGS.clear_width - 0.01


def test_a_narrow_sidewalk_is_all_walkway() -> None:
    city = synthetic_city(SyntheticCityParams(size=(200.0, 200.0), sidewalk=1.4), seed=1)
    plan = geometry_plan(city, CityGeometry(junction_crosswalks=True))
    zones: StreetZones = street_zones(city, plan, SETTINGS)
    residential = [r for r in city.roads if r.highway == "residential"]
    assert residential
    for road in residential:
        strip = LineString(road.centerline.points).buffer(road.width / 2.0 + 1.4)
        assert zones.furniture.intersection(strip).area < 1e-3
