"""A city map written as OSM XML opens in osmnx, with its streets, crossings and buildings."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import osmnx

from navverse.city.osm.reader import read_osm
from navverse.city.osm.writer import write_osm
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city

CITY = synthetic_city(SyntheticCityParams(size=(300.0, 250.0)), seed=7)


def test_osmnx_reads_the_street_network(tmp_path: Path):
    path = write_osm(CITY, tmp_path / "city.osm")
    graph = osmnx.graph_from_xml(path, simplify=False, retain_all=True)
    # osmnx reads every way of a local file (buildings too); the streets are the highway ways.
    kinds = {road.highway for road in CITY.roads}
    streets = [
        d for _, _, d in graph.edges(data=True) if d.get("highway") in kinds and d.get("area") != "yes"
    ]
    assert {d["highway"] for d in streets} == kinds
    crossing_nodes = [n for n, data in graph.nodes(data=True) if data.get("highway") == "crossing"]
    assert len(crossing_nodes) == len(CITY.crossings)
    edge_km = sum(d["length"] for d in streets) / 1000.0
    road_km = sum(r.centerline.length for r in CITY.roads) / 1000.0
    assert abs(edge_km / 2 - road_km) / road_km < 0.02  # two-way streets: an edge each way


def test_buildings_and_areas_carry_their_tags_and_the_bytes_are_stable(tmp_path: Path):
    first = write_osm(CITY, tmp_path / "a.osm").read_bytes()
    assert write_osm(CITY, tmp_path / "b.osm").read_bytes() == first
    root = ET.fromstring(first)
    ways = [{t.get("k"): t.get("v") for t in way.iter("tag")} for way in root.iter("way")]
    buildings = [w for w in ways if w.get("building") == "yes"]
    assert len(buildings) == len(CITY.buildings)
    assert {float(w["height"]) for w in buildings} == {b.height for b in CITY.buildings}
    roads = [w for w in ways if "highway" in w and w.get("area") != "yes"]
    assert all(w["sidewalk"] == "both" and "sidewalk:left:width" in w for w in roads)


def test_the_file_declares_its_window_and_reads_back_without_a_centre(tmp_path: Path):
    path = write_osm(CITY, tmp_path / "city.osm")
    bounds = ET.fromstring(path.read_bytes()).find("bounds")
    assert bounds is not None
    lats = [float(bounds.get(k)) for k in ("minlat", "maxlat")]
    lons = [float(bounds.get(k)) for k in ("minlon", "maxlon")]
    # 300 m x 250 m around (0, 0): one degree is ~111.3 km of latitude, of longitude at the equator.
    assert abs((lons[1] - lons[0]) * 111_320 - 300.0) < 1.0
    assert abs((lats[1] - lats[0]) * 110_574 - 250.0) < 1.0
    again = read_osm(path, size_m=(300.0, 250.0))  # the window: the file's declared bounds
    assert len(again.buildings) == len(CITY.buildings)
    assert {r.highway for r in again.roads} == {r.highway for r in CITY.roads}


def test_crossing_markings_survive_a_round_trip(tmp_path: Path):
    kinds = ("zebra", "lines", "ladder", "dashes", "none")
    crossings = [c.model_copy(update={"markings": kinds[k % 5]}) for k, c in enumerate(CITY.crossings)]
    city = CITY.model_copy(update={"crossings": crossings})
    path = write_osm(city, tmp_path / "city.osm")
    root = ET.fromstring(path.read_bytes())
    written = [{t.get("k"): t.get("v") for t in node.iter("tag")} for node in root.iter("node")]
    assert {n.get("crossing:markings") for n in written if n.get("highway") == "crossing"} == {
        None,
        "lines",
        "ladder",
        "dashes",
        "no",
    }
    again = read_osm(path, size_m=(300.0, 250.0))  # in its own frame: positions within centimetres
    assert len(again.crossings) == len(city.crossings)
    for crossing in city.crossings:
        nearest = min(again.crossings, key=lambda c: math.dist(c.position, crossing.position))
        assert math.dist(nearest.position, crossing.position) < 0.5
        assert nearest.markings == crossing.markings
