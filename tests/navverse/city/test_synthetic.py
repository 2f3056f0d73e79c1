"""Synthetic cities at 1 km²: density, a connected planar street network, buildings clear of the
streets, the water and each other, places in their buildings, furniture of every kind; parameters
bounded; determinism per seed."""

from __future__ import annotations

import functools
import math
import time
from collections import Counter
from pathlib import Path
from typing import get_args

import pytest
import shapely
from pydantic import ValidationError
from shapely.geometry import LineString, Point, Polygon

from navverse.city.map import CityMap, write_city_map
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city
from navverse.city.synthetic.pois import POI_TABLE
from navverse.city.tag_tables import FURNITURE, POI_AMENITIES

LAYOUTS = ("grid", "radial", "organic")
SMALL = {layout: SyntheticCityParams(layout=layout, size=(400.0, 300.0)) for layout in LAYOUTS}
FURNITURE_KINDS = {kind for _, kinds in FURNITURE for kind in kinds}


@functools.cache
def square_km(layout: str) -> tuple[CityMap, float]:
    """The default 1 km × 1 km city of a layout (seed 0) and the seconds it took."""
    start = time.perf_counter()
    city = synthetic_city(SyntheticCityParams(layout=layout), seed=0)
    return city, time.perf_counter() - start


def street_pieces(city: CityMap) -> list[shapely.Geometry]:
    """Each road's carriageway and sidewalks, as plan_surfaces lays them (flat ends, round joins)."""
    return [
        LineString(r.centerline.points).buffer(
            r.width / 2.0 + max(r.sidewalk_left or 0.0, r.sidewalk_right or 0.0), cap_style="flat"
        )
        for r in city.roads
    ]


def junction_angles(city: CityMap) -> list[float]:
    """Angles (degrees) between neighbouring arms at every node where three or more roads meet."""
    arms: dict[tuple[float, float], list[float]] = {}
    for road in city.roads:
        points = road.centerline.points
        for a, b in ((points[0], points[1]), (points[-1], points[-2])):
            arms.setdefault(a, []).append(math.degrees(math.atan2(b[1] - a[1], b[0] - a[0])) % 360.0)
    angles = []
    for directions in arms.values():
        if len(directions) >= 3:
            ordered = sorted(directions)
            angles += [b - a for a, b in zip(ordered, [*ordered[1:], ordered[0] + 360.0], strict=True)]
    return angles


@pytest.mark.parametrize("layout", LAYOUTS)
def test_the_same_seed_gives_the_same_bytes_and_another_seed_another_city(tmp_path: Path, layout: str):
    a = write_city_map(synthetic_city(SMALL[layout], seed=3), tmp_path / "a.json").read_bytes()
    b = write_city_map(synthetic_city(SMALL[layout], seed=3), tmp_path / "b.json").read_bytes()
    c = write_city_map(synthetic_city(SMALL[layout], seed=4), tmp_path / "c.json").read_bytes()
    assert a == b and a != c
    assert synthetic_city(SMALL[layout], seed=3).source.name == layout


def test_the_layouts_differ():
    roads = {layout: synthetic_city(SMALL[layout], seed=1).roads for layout in LAYOUTS}
    assert len({tuple(r.centerline.points[0] for r in rs) for rs in roads.values()}) == 3
    # Only grid streets are all straight and axis-aligned.
    for layout, rs in roads.items():
        axis = all(
            a[0] == b[0] or a[1] == b[1]
            for r in rs
            for a, b in zip(r.centerline.points, r.centerline.points[1:], strict=False)
        )
        assert axis == (layout == "grid")


@pytest.mark.parametrize("layout", LAYOUTS)
def test_a_square_kilometre_has_the_papers_density_quickly(layout: str):
    city, seconds = square_km(layout)
    road_km = sum(road.centerline.length for road in city.roads) / 1000.0
    assert road_km >= 35.0
    assert len(city.buildings) >= 500
    assert seconds < 10.0
    assert {"secondary", "tertiary", "residential"} <= {road.highway for road in city.roads}
    assert len({b.height for b in city.buildings}) >= 5  # varied storeys
    assert {"green", "water", "plaza", "parking"} <= {area.cls for area in city.areas}


@pytest.mark.parametrize("layout", LAYOUTS)
def test_streets_lie_in_the_window_and_meet_only_at_shared_end_points(layout: str):
    city, _ = square_km(layout)
    min_x, min_y, max_x, max_y = city.window
    lines = [LineString(r.centerline.points) for r in city.roads]
    assert all(
        min_x <= x <= max_x and min_y <= y <= max_y for r in city.roads for x, y in r.centerline.points
    )
    assert all(line.is_simple for line in lines)
    tree = shapely.STRtree(lines)
    pairs = tree.query(lines, predicate="intersects")
    for i, j in zip(*pairs, strict=True):
        if i >= j:
            continue
        ends = {city.roads[i].centerline.points[k] for k in (0, -1)} & {
            city.roads[j].centerline.points[k] for k in (0, -1)
        }
        meet = lines[i].intersection(lines[j])
        assert meet.geom_type in ("Point", "MultiPoint"), (city.roads[i].id, city.roads[j].id)
        points = {(p.x, p.y) for p in getattr(meet, "geoms", [meet])}
        assert points <= ends, (city.roads[i].id, city.roads[j].id, points)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_the_street_network_is_connected(layout: str):
    city, _ = square_km(layout)
    parent: dict[tuple[float, float], tuple[float, float]] = {}

    def find(p):
        while parent.setdefault(p, p) != p:
            p = parent[p]
        return p

    for road in city.roads:
        parent[find(road.centerline.points[0])] = find(road.centerline.points[-1])
    assert len({find(p) for p in parent}) == 1


def test_the_organic_layout_has_curved_streets_dead_ends_and_varied_junction_angles():
    city, _ = square_km("organic")
    ends = Counter(p for r in city.roads for p in (r.centerline.points[0], r.centerline.points[-1]))
    min_x, min_y, max_x, max_y = city.window
    inner_dead_ends = [
        p for p, n in ends.items() if n == 1 and min_x + 1 < p[0] < max_x - 1 and min_y + 1 < p[1] < max_y - 1
    ]
    assert len(inner_dead_ends) >= 10
    curved = [r for r in city.roads if len(r.centerline.points) > 2]
    assert len(curved) > len(city.roads) / 2
    organic = Counter(round(a / 5.0) * 5 for a in junction_angles(city))
    assert len(organic) >= 15 and max(organic.values()) < 0.3 * sum(organic.values())
    grid = {round(a, 6) for a in junction_angles(square_km("grid")[0])}
    assert grid <= {90.0, 180.0, 270.0}


@pytest.mark.parametrize("layout", LAYOUTS)
def test_buildings_stand_clear_of_streets_water_and_each_other(layout: str):
    city, _ = square_km(layout)
    setback = SyntheticCityParams().setback
    streets = shapely.STRtree(street_pieces(city))
    water = [Polygon(a.polygon.exterior, a.polygon.holes) for a in city.areas if a.cls == "water"]
    assert sum(w.area for w in water) > 10_000.0  # a river crosses the window
    footprints = [Polygon(b.footprint.exterior) for b in city.buildings]
    assert all(f.is_valid and f.is_simple and len(f.exterior.coords) == 5 for f in footprints)
    assert all(abs(f.area - f.convex_hull.area) < 1e-3 for f in footprints)
    # The setback (less rounding) from every carriageway and sidewalk; off the water.
    assert streets.query(footprints, predicate="dwithin", distance=setback - 0.01).size == 0
    assert shapely.STRtree(water).query(footprints, predicate="intersects").size == 0
    tree = shapely.STRtree(footprints)
    for i, j in zip(*tree.query(footprints, predicate="intersects"), strict=True):
        assert i == j or footprints[i].intersection(footprints[j]).area < 1e-6
    assert all(b.base_height == 0.0 and b.height == b.levels * 3.0 for b in city.buildings)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_only_bridges_cross_the_river(layout: str):
    city, _ = square_km(layout)
    (river,) = [
        Polygon(a.polygon.exterior)
        for a in city.areas
        if a.cls == "water" and a.polygon.exterior and Polygon(a.polygon.exterior).area > 10_000.0
    ]
    over = [r for r in city.roads if LineString(r.centerline.points).intersects(river)]
    bridges = {r.name for r in over}
    assert bridges, "the river is crossed"
    assert len(bridges) <= SyntheticCityParams().bridges  # by the bridges only


@pytest.mark.parametrize("layout", LAYOUTS)
def test_places_stand_inside_their_buildings_at_a_street_facade(layout: str):
    city, _ = square_km(layout)
    buildings = {b.id: b for b in city.buildings}
    streets = shapely.STRtree(street_pieces(city))
    assert len(city.pois) >= 100
    assert len({p.category for p in city.pois}) >= 17
    assert len({p.name for p in city.pois}) >= len(city.pois) / 3
    for poi in city.pois:
        building = buildings[poi.building]
        footprint = Polygon(building.footprint.exterior)
        assert footprint.contains(Point(poi.position))
        assert footprint.exterior.distance(Point(poi.position)) == pytest.approx(0.5, abs=0.01)
        assert poi.tag == f"{poi.tag.split('=')[0]}={poi.category}" and poi.name
        assert any(footprint.exterior.distance(Point(e)) < 0.002 for e in building.entrances)
        # The facade it stands behind faces a street: the sidewalk is within the setback (plus up to
        # 1.25 m where the street curves).
        door = min(building.entrances, key=lambda e: Point(e).distance(Point(poi.position)))
        reach = SyntheticCityParams().setback + 1.25
        assert streets.query(Point(door), predicate="dwithin", distance=reach).size
    amenities = {p.category for p in city.pois if p.tag.startswith("amenity=")}
    assert amenities <= POI_AMENITIES


def test_the_place_table_is_a_frequency_table_of_common_osm_values():
    categories = [value for _, value, _, _ in POI_TABLE]
    assert len(set(categories)) == len(categories) >= 17
    for needed in (
        "cafe",
        "restaurant",
        "fast_food",
        "bank",
        "pharmacy",
        "bar",
        "supermarket",
        "convenience",
    ):
        assert needed in categories
    for needed in ("bakery", "clothes", "hairdresser", "books", "florist", "hardware"):
        assert needed in categories
    assert all(weight >= 1 for _, _, weight, _ in POI_TABLE)
    assert {key for key, _, _, _ in POI_TABLE} == {"amenity", "shop"}


@pytest.mark.parametrize("layout", LAYOUTS)
def test_every_kind_of_street_furniture_stands_off_the_carriageways(layout: str):
    city, _ = square_km(layout)
    kinds = Counter(f.kind for f in city.furniture)
    assert set(kinds) == FURNITURE_KINDS
    assert kinds["street_lamp"] > 500 and kinds["tree"] > 500
    carriageways = shapely.STRtree(
        [LineString(r.centerline.points).buffer(r.width / 2.0) for r in city.roads]
    )
    points = shapely.points([f.position for f in city.furniture])
    assert carriageways.query(points, predicate="intersects").size == 0
    buildings = shapely.STRtree([Polygon(b.footprint.exterior) for b in city.buildings])
    assert buildings.query(points, predicate="intersects").size == 0
    # Traffic signals stand at junctions an arterial reaches.
    arterial_ends = shapely.STRtree(
        [
            Point(p)
            for r in city.roads
            if r.highway in ("secondary", "tertiary")
            for p in (r.centerline.points[0], r.centerline.points[-1])
        ]
    )
    signals = shapely.points([f.position for f in city.furniture if f.kind == "traffic_signals"])
    assert len(signals) > 20
    _, distances = arterial_ends.query_nearest(signals, return_distance=True)
    assert distances.max() < 40.0


def test_parameters_are_bounded_and_unknown_ones_refused():
    with pytest.raises(ValidationError):
        SyntheticCityParams(layout="hexagonal")
    with pytest.raises(ValidationError):
        SyntheticCityParams(blocks=(60.0, 40.0))
    with pytest.raises(ValidationError):
        SyntheticCityParams(node_jitter=0.3)  # a quarter of the spacing or more could cross streets
    with pytest.raises(ValidationError):
        SyntheticCityParams(size=(10_000.0, 100.0))
    with pytest.raises(ValidationError):
        SyntheticCityParams(park_share=1.5)
    numbers = 0
    for name, field in SyntheticCityParams.model_fields.items():
        if name == "layout":
            continue
        # A number carries its bounds; a pair carries them on each element.
        parts = [field.metadata] if field.annotation in (float, int) else []
        parts += [get_args(a)[1].metadata for a in get_args(field.annotation) if get_args(a)]
        assert parts, name
        for metadata in parts:
            bounds = {type(m).__name__ for m in metadata}
            assert bounds & {"Ge", "Gt"} and bounds & {"Le", "Lt"}, name
            numbers += 1
    assert numbers >= 40
