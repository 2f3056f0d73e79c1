"""Synthetic grid cities: deterministic per seed, plausible density, buildings clear of the streets."""

from __future__ import annotations

from pathlib import Path

import pytest
import shapely
from shapely.geometry import LineString, Polygon

from navverse.city.map import write_city_map
from navverse.city.surfaces import plan_surfaces
from navverse.city.synthetic import SyntheticCityParams, synthetic_city

SMALL = SyntheticCityParams(size=(400.0, 300.0))


def test_the_same_seed_gives_the_same_bytes_and_another_seed_another_city(tmp_path: Path):
    a = write_city_map(synthetic_city(SMALL, seed=3), tmp_path / "a.json").read_bytes()
    b = write_city_map(synthetic_city(SMALL, seed=3), tmp_path / "b.json").read_bytes()
    c = write_city_map(synthetic_city(SMALL, seed=4), tmp_path / "c.json").read_bytes()
    assert a == b and a != c


def test_a_square_kilometre_has_a_city_density():
    city = synthetic_city(SyntheticCityParams(), seed=0)
    road_km = sum(road.centerline.length for road in city.roads) / 1000.0
    assert 15.0 <= road_km <= 40.0
    assert 400 <= len(city.buildings) <= 3000
    assert any(area.cls == "green" for area in city.areas)
    assert any(road.highway == "secondary" for road in city.roads)
    heights = {b.height for b in city.buildings}
    assert len(heights) > 3  # varied storeys


def test_buildings_stand_clear_of_roads_and_sidewalks_and_of_each_other():
    city = synthetic_city(SMALL, seed=1)
    streets = shapely.union_all(
        [
            LineString(r.centerline.points).buffer(r.width / 2.0 + (r.sidewalk_left or 0.0), cap_style="flat")
            for r in city.roads
        ]
    )
    footprints = [Polygon(b.footprint.exterior) for b in city.buildings]
    assert footprints
    assert all(f.intersection(streets).area < 1e-6 for f in footprints)
    tree = shapely.STRtree(footprints)
    for i, footprint in enumerate(footprints):
        for j in tree.query(footprint, predicate="intersects"):
            assert j == i or footprint.intersection(footprints[j]).area < 1e-6


def test_every_crossing_lies_on_the_road_it_names():
    city = synthetic_city(SMALL, seed=2)
    roads = {road.id: road for road in city.roads}
    assert city.crossings
    for crossing in city.crossings:
        road = roads[crossing.road]
        assert LineString(road.centerline.points).distance(shapely.Point(crossing.position)) < 1e-6


def test_the_ground_plan_of_a_synthetic_city_tiles_its_window():
    city = synthetic_city(SMALL, seed=5)
    plan = plan_surfaces(city)
    assert sum(g.area for g in plan.values()) == pytest.approx(400.0 * 300.0, rel=1e-6)
    assert plan["crosswalk"].area > 0 and plan["lowered_curb"].area > 0 and plan["building"].area > 0
