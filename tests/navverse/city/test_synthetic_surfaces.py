"""Small synthetic cities of every layout through the rest of the toolkit: the ground plan tiles the
window with furniture on its sidewalks and crosswalks at the junctions, osmnx reads the written OSM
file; the optional knobs (no river, living streets, service roads) and a 4 km² city."""

from __future__ import annotations

import functools
import math
import time
from collections import Counter
from pathlib import Path

import osmnx
import pytest
import shapely
from shapely.geometry import LineString, Point, box

from navverse.city.geometry.surfaces import CROSSWALK_WIDTH, CURB_WIDTH, _crosswalk, plan_surfaces
from navverse.city.map import CityMap
from navverse.city.osm.writer import write_osm
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city

LAYOUTS = ("grid", "radial", "organic")


@functools.cache
def small(layout: str) -> CityMap:
    return synthetic_city(SyntheticCityParams(layout=layout, size=(400.0, 300.0)), seed=11)


@functools.cache
def plan(layout: str) -> dict[str, shapely.Geometry]:
    return plan_surfaces(small(layout), curb_width=CURB_WIDTH, crosswalk_width=CROSSWALK_WIDTH)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_the_ground_plan_tiles_the_window_with_every_surface(layout: str):
    surfaces = plan(layout)
    assert sum(g.area for g in surfaces.values()) == pytest.approx(400.0 * 300.0, rel=1e-6)
    for cls in ("road", "sidewalk", "curb", "crosswalk", "lowered_curb", "building", "water", "green"):
        assert surfaces[cls].area > 0, cls


@pytest.mark.parametrize("layout", LAYOUTS)
def test_street_furniture_stands_on_sidewalks(layout: str):
    city = small(layout)
    sidewalk = plan(layout)["sidewalk"]
    shapely.prepare(sidewalk)
    assert len(city.furniture) > 100
    points = shapely.points([f.position for f in city.furniture])
    off = [f for f, on in zip(city.furniture, shapely.contains(sidewalk, points), strict=True) if not on]
    assert not off, off[:5]
    xy = [f.position for f in city.furniture]
    assert min(math.dist(a, b) for i, a in enumerate(xy) for b in xy[i + 1 :]) >= 1.0 - 1e-9


@pytest.mark.parametrize("layout", LAYOUTS)
def test_crossings_sit_on_junction_arms_of_their_roads(layout: str):
    city = small(layout)
    roads = {road.id: road for road in city.roads}
    degree = Counter(p for r in city.roads for p in (r.centerline.points[0], r.centerline.points[-1]))
    junctions = [Point(p) for p, n in degree.items() if n >= 3]
    assert len(city.crossings) >= len(junctions)  # most junctions have several crossed arms
    for crossing in city.crossings:
        road = roads[crossing.road]
        line = LineString(road.centerline.points)
        where = Point(crossing.position)
        assert line.distance(where) < 1e-3  # millimetre coordinates
        ends = [Point(road.centerline.points[0]), Point(road.centerline.points[-1])]
        nearest = min(ends, key=where.distance)
        assert degree[(nearest.x, nearest.y)] >= 3
        assert 2.0 < where.distance(nearest) < 40.0
    # Every crosswalk lies on the carriageway, clear of the crossing roads' junction area.
    assert plan(layout)["crosswalk"].area > 0.9 * len(city.crossings) * 4.0 * 5.5


@pytest.mark.parametrize("layout", LAYOUTS)
def test_crosswalks_stay_off_the_other_streets_of_their_junction(layout: str):
    city = small(layout)
    roads = {road.id: road for road in city.roads}
    strips = [
        LineString(r.centerline.points).buffer(
            r.width / 2.0 + max(r.sidewalk_left or 0.0, r.sidewalk_right or 0.0)
        )
        for r in city.roads
    ]
    tree = shapely.STRtree(strips)
    for crossing in city.crossings:
        crosswalk = _crosswalk(roads[crossing.road], crossing.position, CROSSWALK_WIDTH)
        for k in tree.query(crosswalk, predicate="intersects"):
            if city.roads[k].id != crossing.road:
                assert crosswalk.intersection(strips[k]).area < 1e-3, (crossing.id, city.roads[k].id)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_osmnx_reads_the_written_osm_file(tmp_path: Path, layout: str):
    city = small(layout)
    graph = osmnx.graph_from_xml(write_osm(city, tmp_path / "city.osm"), simplify=False, retain_all=True)
    kinds = {road.highway for road in city.roads}
    streets = [
        d for _, _, d in graph.edges(data=True) if d.get("highway") in kinds and d.get("area") != "yes"
    ]
    assert {d["highway"] for d in streets} == kinds
    crossing_nodes = [n for n, data in graph.nodes(data=True) if data.get("highway") == "crossing"]
    assert len(crossing_nodes) == len(city.crossings)
    edge_km = sum(d["length"] for d in streets) / 1000.0
    road_km = sum(r.centerline.length for r in city.roads) / 1000.0
    assert abs(edge_km / 2 - road_km) / road_km < 0.02


def test_the_knobs_turn_off_the_river_and_make_living_streets_and_service_roads():
    params = SyntheticCityParams(
        layout="organic",
        size=(400.0, 300.0),
        river_width=0.0,
        living_street_share=0.3,
        service_share=1.0,
        street_removal=0.5,
        pond_share=1.0,
        park_share=0.3,
    )
    city = synthetic_city(params, seed=2)
    kinds = Counter(road.highway for road in city.roads)
    assert kinds["living_street"] > 0 and kinds["service"] > 0
    for road in city.roads:
        if road.highway in ("living_street", "service"):
            assert road.sidewalk_left is None and road.sidewalk_right is None
    bare = {road.id for road in city.roads if road.sidewalk_left is None}
    assert not any(crossing.road in bare for crossing in city.crossings)
    water = [a for a in city.areas if a.cls == "water"]
    assert water  # ponds, no river
    parks = [shapely.Polygon(a.polygon.exterior, a.polygon.holes) for a in city.areas if a.cls == "green"]
    for pond in water:
        shape = shapely.Polygon(pond.polygon.exterior)
        # A hole in a park: inside its outline, off its grass.
        assert any(
            shapely.Polygon(p.exterior).contains(shape) and p.intersection(shape).area < 1e-6 for p in parks
        )
        assert shape.area < 0.5 * max(p.area for p in parks)
    # the bare roads have no sidewalk strips; the plan still tiles the window
    plan_surfaces(city, curb_width=CURB_WIDTH, crosswalk_width=CROSSWALK_WIDTH)


def test_a_four_square_kilometre_city_takes_about_four_times_as_long():
    start = time.perf_counter()
    city = synthetic_city(SyntheticCityParams(size=(2000.0, 2000.0)), seed=5)
    seconds = time.perf_counter() - start
    assert seconds < 40.0
    road_km = sum(r.centerline.length for r in city.roads) / 1000.0
    assert road_km > 4 * 30.0 and len(city.buildings) > 4 * 500
    window = box(*city.window)
    assert all(window.covers(shapely.Polygon(b.footprint.exterior)) for b in city.buildings)
