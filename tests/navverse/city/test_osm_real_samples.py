"""The OSM reader on small samples of real extracts (cut by scripts/cut_osm_sample.py; see
data/real/README.md): buildings in parts, separately mapped sidewalks, a plaza, bridges kept and left
out, a building passage into a courtyard, clipped ways, a file without bounds, gzip and bzip2 XML
recognised by their content."""

from __future__ import annotations

import bz2
import gzip
import shutil
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString

from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.map import CityMap, write_city_map
from navverse.city.osm import features
from navverse.city.osm.geometry import polygon_of
from navverse.city.osm.reader import check_window, read_osm
from navverse.nav import OUTDOOR
from navverse.nav.scene_navmesh import build_scene_navmesh

REAL = Path(__file__).parent / "data" / "real"
SIDE = (160.0, 160.0)


def _read(name: str | Path) -> CityMap:
    """A sample (by name) or any file (by path) read in a window of :data:`SIDE` around its data."""
    return read_osm(REAL / name, size_m=SIDE)


def _same_map(a: CityMap, b: CityMap) -> bool:
    """Whether two maps hold the same features (their sources' names and checksums aside)."""
    keep = {"source"}
    return a.model_dump(exclude=keep) == b.model_dump(exclude=keep)


def test_a_building_mapped_in_parts_stands_as_its_parts_not_twice() -> None:
    city = _read("berlin-grosser-stern-column.osm.gz")
    parts = [b for b in city.buildings if b.outline == "way/56226088"]  # the Victory Column's parts
    rest = [b for b in city.buildings if b.osm == "way/56226088"]
    assert len(parts) >= 15 and len(rest) == 1 and rest[0].outline is None
    # The parts stack: each part's base is another part's top, up to the statue at the top.
    tops = {round(p.height, 2) for p in parts} | {round(rest[0].height, 2)}
    assert all(round(p.base_height, 2) in tops for p in parts if p.base_height > rest[0].height)
    assert max(p.height for p in parts) > 50.0 and all(p.height_source == "height" for p in parts)
    # Nothing is counted twice: the rest of the outline does not overlap its parts.
    outline_rest = polygon_of(rest[0].footprint)
    for part in parts:
        assert outline_rest.intersection(polygon_of(part.footprint)).area < 0.01
    assert {b.type for b in city.buildings} == {"yes"}
    assert "building:part (ignored; the building outline carries the building)" not in city.dropped


def _sides(city: CityMap) -> int:
    return sum((r.sidewalk_left is not None) + (r.sidewalk_right is not None) for r in city.roads)


def _doubled_area(city: CityMap) -> float:
    """Area where the roads' own sidewalk strips overlap the mapped sidewalks (m²)."""
    mapped = shapely.union_all(
        [LineString(w.centerline.points).buffer(w.width / 2.0) for w in city.walkways if w.kind == "sidewalk"]
    )
    strips = []
    for road in city.roads:
        line = LineString(road.centerline.points)
        for width, sign in ((road.sidewalk_left, 1.0), (road.sidewalk_right, -1.0)):
            if width is not None:
                strips.append(line.buffer(sign * (road.width / 2.0 + width), single_sided=True))
    return shapely.union_all(strips).intersection(mapped).area if strips else 0.0


def test_mapped_sidewalks_are_not_doubled_by_inferred_ones(monkeypatch: pytest.MonkeyPatch) -> None:
    city = _read("sydney-sydenham-sidewalks.osm")
    assert city.dropped["inferred sidewalk left out (a mapped sidewalk runs beside the road)"] == 3
    # Inferring every side by the class rule would lay three strips over the mapped sidewalks.
    monkeypatch.setattr(features._Builder, "undoubled", lambda self, roads, walkways: roads)
    doubled = _read("sydney-sydenham-sidewalks.osm")
    assert _sides(doubled) == _sides(city) + 3
    assert _doubled_area(city) < 0.2 * _doubled_area(doubled)


def test_a_pedestrian_square_is_a_plaza_in_the_map_and_the_plan() -> None:
    city = _read("munich-marienplatz.osm.gz")
    square = [a for a in city.areas if a.osm == "relation/7366154"]  # Marienplatz
    assert square and all(a.cls == "plaza" for a in square)
    assert sum(polygon_of(a.polygon).area for a in square) > 5000.0
    plan = geometry_plan(city, CityGeometry())
    assert plan.classes["plaza"].area > 5000.0
    assert sum(1 for w in city.walkways if w.kind == "pedestrian") >= 10


def test_a_bridge_over_a_river_is_kept_and_an_overpass_is_left_out() -> None:
    berlin = _read("berlin-weidendamm-bridge.osm.xml.gz")
    bridge = [r for r in berlin.roads if r.osm == "way/6228081"]  # Weidendammer Bruecke over the Spree
    water = shapely.union_all([polygon_of(a.polygon) for a in berlin.areas if a.cls == "water"])
    assert bridge and any(LineString(r.centerline.points).crosses(water) for r in bridge)
    assert berlin.dropped["bridge over water or rail (kept level with the streets)"] == 3
    seattle = _read("seattle-i5-overpass.osm")
    assert all(r.highway != "motorway" for r in seattle.roads)  # I-5 runs over the streets here
    assert seattle.dropped["bridge over a way at ground level (left out)"] == 4
    assert seattle.dropped["bridge over neither water nor rail (left out)"] == 4
    scene = city_scene(berlin, scene_id="bridge", geometry=CityGeometry())
    assert {s.terrain_class for s in scene.surfaces} >= {"road", "water", "sidewalk"}


def test_a_building_passage_leads_under_the_building_into_its_courtyard() -> None:
    city = _read("berlin-hinterhof-passage.osm.gz")
    # A driveway through the front building (tunnel=building_passage, covered=yes) into a Hinterhof.
    passage = [r for r in city.roads if r.osm == "way/585841588"]
    courtyard = [r for r in city.roads if r.osm == "way/566154988"]
    assert passage and courtyard
    line = LineString(passage[0].centerline.points)
    front = [b for b in city.buildings if b.osm == "way/23748217"]
    over = [b for b in front if b.base_height == 3.5]  # no maxheight: the default headroom
    assert len(over) == 1 and polygon_of(over[0].footprint).intersection(line).length > 5.0
    standing = [polygon_of(b.footprint) for b in city.buildings if b.base_height == 0.0]
    assert all(shape.intersection(line).length < 0.01 for shape in standing)
    assert (
        city.dropped["building raised over a passage at ground level (tunnel=building_passage, covered)"] == 3
    )
    scene = city_scene(city, scene_id="passage", geometry=CityGeometry())
    finder = build_scene_navmesh(scene, OUTDOOR, jobs=2)
    # The courtyard's driveway, the passage and the street are one island.
    points = [
        (*LineString(r.centerline.points).interpolate(0.5, normalized=True).coords[0], 0.0)
        for r in city.roads
    ]
    islands = finder.island_of(np.array(points))
    ids = [r.id for r in city.roads]
    assert islands[ids.index(passage[0].id)] == islands[ids.index(courtyard[0].id)] == finder.largest_island


def test_ways_clipped_at_the_extract_edge_are_split_and_counted() -> None:
    city = _read("essen-clipped.osm")
    assert city.dropped["way with missing nodes (kept the parts between them)"] == 2
    assert city.dropped["polygon way with missing nodes (too few nodes left; dropped)"] == 8
    assert city.dropped["polygon way with missing nodes (skipped them)"] == 11
    assert len(city.buildings) == 39 and len(city.roads) == 5
    assert all(polygon_of(b.footprint).is_valid for b in city.buildings)
    city_scene(city, scene_id="clipped", geometry=CityGeometry())


def test_a_file_without_bounds_is_read_around_its_data() -> None:
    path = REAL / "berlin-weidendamm-bridge.osm.xml.gz"
    with gzip.open(path, "rt", encoding="utf-8") as handle:
        assert "<bounds" not in handle.read()
    check_window(path)  # no bounds to check a centre against: checked when read
    city = read_osm(path, size_m=SIDE)
    assert abs(city.frame.origin_lat - 52.522) < 1e-3 and abs(city.frame.origin_lon - 13.388) < 1.5e-3
    assert len(city.roads) == 14 and len(city.buildings) == 9


def test_gzip_and_bzip2_xml_are_recognised_by_their_content(tmp_path: Path) -> None:
    gz = REAL / "berlin-weidendamm-bridge.osm.xml.gz"
    unnamed = tmp_path / "download"  # how a browser may save an Overpass export
    shutil.copyfile(gz, unnamed)
    assert _same_map(read_osm(unnamed, size_m=SIDE), read_osm(gz, size_m=SIDE))
    plain = REAL / "sydney-sydenham-sidewalks.osm"
    bzipped = tmp_path / "sydenham.osm.bz2"
    bzipped.write_bytes(bz2.compress(plain.read_bytes()))
    from_bz2, from_xml = _read(bzipped), _read(plain)
    assert _same_map(from_bz2, from_xml) and from_bz2.source.name == "sydenham.osm.bz2"
    write_city_map(from_bz2, tmp_path / "a.json")
    write_city_map(_read(bzipped), tmp_path / "b.json")
    assert (tmp_path / "a.json").read_bytes() == (tmp_path / "b.json").read_bytes()


@pytest.mark.parametrize("name", sorted(p.name for p in REAL.glob("*.osm*")))
def test_every_sample_builds_a_city(name: str) -> None:
    city = _read(name)
    scene = city_scene(city, scene_id="sample", geometry=CityGeometry())
    assert scene.surfaces and scene.annotations.buildings
