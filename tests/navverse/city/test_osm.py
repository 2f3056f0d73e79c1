"""Reading city maps from OSM files: a hand-laid T-junction, the real extracts, hostile and messy input."""

from __future__ import annotations

import bz2
import gzip
import math
import os
from pathlib import Path

import numpy as np
import osmium
import pytest
import shapely
from pyproj import Transformer
from shapely.geometry import LineString, Polygon

from navverse.city.geometry.scene import CityGeometry, geometry_plan
from navverse.city.map import CityMap, CityMapError, read_city_map, write_city_map
from navverse.city.osm.files import PROLOG_LIMIT
from navverse.city.osm.geometry import clip_polyline
from navverse.city.osm.reader import OSM_ATTRIBUTION, read_osm
from navverse.city.osm.window import utm_epsg
from navverse.city.tag_tables import (
    crossing_markings,
    drawn_storeys,
    kerb_of,
    land_class,
    parking_sides,
    poi_of,
    walkway_kind,
)

DATA = Path(__file__).parent / "data"
T_JUNCTION = DATA / "t_junction.osm"
RAW = Path(__file__).parents[3] / "data" / "raw" / "osm"
EXTRACTS = {  # file: (UTM EPSG, minimum roads, minimum buildings)
    "aguascalientes.osm": (32613, 100, 1),
    "west-oakland.osm": (32610, 15, 20),
    "kirchberg-an-der-iller.osm": (32632, 10, 30),
}

_TO_LONLAT = Transformer.from_crs("EPSG:32632", "EPSG:4326", always_xy=True)
_ORIGIN = Transformer.from_crs("EPSG:4326", "EPSG:32632", always_xy=True).transform(11.0, 48.0)


def _area(polygon) -> float:
    return _shape_of(polygon).area


def _shape_of(polygon) -> Polygon:
    return Polygon(polygon.exterior, polygon.holes)


def _shape(building) -> Polygon:
    return _shape_of(building.footprint)


def _osm_xml(nodes: dict, ways: dict, relations: dict | None = None) -> str:
    """OSM XML from nodes {id: (x, y, tags)} in meters around 48 N 11 E, ways {id: (refs, tags)} and
    relations {id: (members [(type, ref, role)], tags)}."""
    lines = ["<?xml version='1.0' encoding='UTF-8'?>", '<osm version="0.6">']
    lines.append('  <bounds minlat="47.998" minlon="10.997" maxlat="48.002" maxlon="11.003"/>')

    def tags_xml(tags: dict) -> list[str]:
        return [f'    <tag k="{k}" v="{v}"/>' for k, v in tags.items()]

    for node_id, (x, y, tags) in nodes.items():
        lon, lat = _TO_LONLAT.transform(_ORIGIN[0] + x, _ORIGIN[1] + y)
        lines += [f'  <node id="{node_id}" lat="{lat:.7f}" lon="{lon:.7f}">', *tags_xml(tags), "  </node>"]
    for way_id, (refs, tags) in ways.items():
        lines += [
            f'  <way id="{way_id}">',
            *[f'    <nd ref="{r}"/>' for r in refs],
            *tags_xml(tags),
            "  </way>",
        ]
    for relation_id, (members, tags) in (relations or {}).items():
        lines.append(f'  <relation id="{relation_id}">')
        lines += [f'    <member type="{t}" ref="{r}" role="{role}"/>' for t, r, role in members]
        lines += [*tags_xml(tags), "  </relation>"]
    return "\n".join([*lines, "</osm>", ""])


def _write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


def _to_pbf(source: Path, target: Path) -> Path:
    writer = osmium.SimpleWriter(str(target))
    try:
        for obj in osmium.FileProcessor(str(source)):
            {"n": writer.add_node, "w": writer.add_way, "r": writer.add_relation}[obj.type_str()](obj)
    finally:
        writer.close()
    return target


def _without_source(city: CityMap) -> dict:
    data = city.model_dump(mode="json", by_alias=True)
    data.pop("source")
    return data


@pytest.fixture(scope="module")
def junction() -> CityMap:
    return read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))


# The hand-laid T-junction ------------------------------------------------------------------------


def test_junction_frame_source_and_window(junction: CityMap) -> None:
    assert junction.frame.epsg == 32632
    assert (junction.frame.origin_lat, junction.frame.origin_lon) == (48.0, 11.0)
    assert junction.window == (-100.0, -100.0, 100.0, 100.0)
    assert junction.source.kind == "osm" and junction.source.name == "t_junction.osm"
    assert junction.source.attribution == OSM_ATTRIBUTION
    assert len(junction.source.sha256) == 64
    assert junction.dropped == {}


def test_junction_roads_widths_and_sidewalks(junction: CityMap) -> None:
    main, side = junction.roads
    assert main.osm == "way/100" and main.name == "Hauptstraße" and main.surface == "asphalt"
    assert (main.width, main.width_source, main.lanes) == (7.0, "width", 2)
    assert (main.sidewalk_left, main.sidewalk_right, main.sidewalk_source) == (1.5, 1.5, "tags")
    assert side.osm == "way/101"
    assert (side.width, side.width_source, side.lanes) == (6.5, "default", None)
    assert (side.sidewalk_left, side.sidewalk_right, side.sidewalk_source) == (1.5, 1.5, "rule")
    # local meters: the main street runs west to east through the origin, within centimetres
    assert main.centerline.points[0] == pytest.approx((-80.0, 0.0), abs=0.02)
    assert main.centerline.points[-1] == pytest.approx((80.0, 0.0), abs=0.02)
    assert side.centerline.length == pytest.approx(80.0, abs=0.05)


def test_junction_crossing_names_its_road(junction: CityMap) -> None:
    (crossing,) = junction.crossings
    assert crossing.osm == "node/4"
    assert crossing.road == junction.roads[0].id
    assert (crossing.kerb, crossing.markings) == ("lowered", "zebra")  # crossing=marked
    assert crossing.position == pytest.approx((-20.0, 0.0), abs=0.02)
    (walkway,) = junction.walkways
    assert (walkway.kind, walkway.width) == ("crossing", 2.0)


def test_junction_buildings_heights_hole_and_entrance(junction: CityMap) -> None:
    by_osm = {b.osm: b for b in junction.buildings}
    shop, house, courtyard = by_osm["way/110"], by_osm["way/111"], by_osm["relation/200"]
    assert (shop.height, shop.height_source) == (12.0, "height")
    assert (house.height, house.height_source, house.levels) == (9.0, "levels", 3.0)
    assert (courtyard.height, courtyard.levels) == (12.0, 4.0)
    assert len(courtyard.footprint.holes) == 1
    assert _area(courtyard.footprint) == pytest.approx(40 * 40 - 20 * 20, rel=0.01)
    assert shop.entrances == [pytest.approx((25.0, -10.0), abs=0.02)]
    # the relation's untagged member ways are not buildings of their own
    assert len(junction.buildings) == 3


def test_junction_park_poi_and_tree(junction: CityMap) -> None:
    (park,) = junction.areas
    assert park.cls == "green" and park.osm == "way/114"
    assert _area(park.polygon) == pytest.approx(1600.0, rel=0.01)
    (poi,) = junction.pois
    shop = next(b for b in junction.buildings if b.osm == "way/110")
    assert (poi.category, poi.tag, poi.name, poi.building) == ("cafe", "amenity=cafe", "Café Eck", shop.id)
    (tree,) = junction.furniture
    assert tree.kind == "tree" and tree.position == pytest.approx((-40.0, -40.0), abs=0.02)


def test_junction_round_trips_byte_identical(junction: CityMap, tmp_path: Path) -> None:
    again = read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))
    first, second = write_city_map(junction, tmp_path / "a.json"), write_city_map(again, tmp_path / "b.json")
    assert first.read_bytes() == second.read_bytes()
    assert read_city_map(first) == junction


def test_small_window_clips_features_crossing_its_edge() -> None:
    city = read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(60.0, 60.0))
    main = next(r for r in city.roads if r.osm == "way/100")
    xs = [p[0] for p in main.centerline.points]
    assert xs[0] == pytest.approx(-30.0, abs=1e-3) and xs[-1] == pytest.approx(30.0, abs=1e-3)  # west to east
    (park,) = city.areas
    assert _area(park.polygon) == pytest.approx(10.0 * 10.0, rel=0.02)  # (-30..-20, -30..-20)
    for feature in [*city.roads, *city.walkways]:
        assert all(abs(x) <= 30.0 and abs(y) <= 30.0 for x, y in feature.centerline.points)
    courtyard = next(b for b in city.buildings if b.osm == "relation/200")
    assert not courtyard.footprint.holes  # its courtyard (-50..-30, 20..40) is outside the window
    assert _area(courtyard.footprint) == pytest.approx(10.0 * 20.0, rel=0.01)  # (-30..-20, 10..30)
    assert {p.osm for p in city.pois} == {"node/30"}


def test_bbox_window_is_centred_on_the_box() -> None:
    city = read_osm(T_JUNCTION, bbox=(47.9995, 10.9990, 48.0005, 11.0010))
    assert (city.frame.origin_lat, city.frame.origin_lon) == (48.0, 11.0)
    min_x, min_y, max_x, max_y = city.window
    assert min_x < -70 and max_x > 70 and min_y < -55 and max_y > 55
    assert {r.osm for r in city.roads} == {"way/100", "way/101"}


def test_default_window_is_centred_on_the_file_bounds() -> None:
    city = read_osm(T_JUNCTION)
    assert (city.frame.origin_lat, city.frame.origin_lon) == (48.0, 11.0)
    assert city.window == (-500.0, -500.0, 500.0, 500.0)


def test_progress_is_reported() -> None:
    calls: list[tuple[str, int]] = []
    read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0), progress=lambda *a: calls.append(a))
    assert calls[-1][0] == "read" and calls[-1][1] > 0


# The real extracts -------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(EXTRACTS))
def test_real_extracts_load_with_plausible_counts(name: str, tmp_path: Path) -> None:
    epsg, min_roads, min_buildings = EXTRACTS[name]
    city = read_osm(RAW / name)
    assert city.frame.epsg == epsg
    assert len(city.roads) >= min_roads and len(city.buildings) >= min_buildings
    assert all(r.width > 0 for r in city.roads)
    assert all(b.height > b.base_height for b in city.buildings)
    road_ids = {r.id for r in city.roads}
    assert all(c.road in road_ids for c in city.crossings)
    again = read_osm(RAW / name)
    first, second = write_city_map(city, tmp_path / "a.json"), write_city_map(again, tmp_path / "b.json")
    assert first.read_bytes() == second.read_bytes()


def test_real_extract_counts_its_messy_data() -> None:
    city = read_osm(RAW / "kirchberg-an-der-iller.osm")
    # two building/area ways of a single node, a self-intersecting building, two multipolygons whose
    # outer ways the extract cut open
    assert city.dropped["building or area way that is not a closed ring"] == 2
    assert city.dropped["invalid polygon (self-intersecting or overlapping rings; repaired)"] == 1
    assert city.dropped["multipolygon that could not be assembled"] == 2


def test_gzip_and_pbf_give_the_same_map_as_xml(tmp_path: Path) -> None:
    source = RAW / "west-oakland.osm"
    gz = tmp_path / "west-oakland.osm.gz"
    gz.write_bytes(gzip.compress(source.read_bytes(), mtime=0))
    pbf = _to_pbf(source, tmp_path / "west-oakland.osm.pbf")
    center = (37.80765, -122.30042)
    expected = _without_source(read_osm(source, center=center, size_m=(400.0, 400.0)))
    assert _without_source(read_osm(gz, center=center, size_m=(400.0, 400.0))) == expected
    assert _without_source(read_osm(pbf, center=center, size_m=(400.0, 400.0))) == expected


# Hostile and wrong input -------------------------------------------------------------------------


def test_truncated_xml_is_refused(tmp_path: Path) -> None:
    data = (RAW / "aguascalientes.osm").read_bytes()
    path = tmp_path / "cut.osm"
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(CityMapError, match="truncated"):
        read_osm(path)


def test_truncated_pbf_and_gzip_are_refused(tmp_path: Path) -> None:
    pbf = _to_pbf(RAW / "west-oakland.osm", tmp_path / "whole.osm.pbf")
    cut = tmp_path / "cut.osm.pbf"
    cut.write_bytes(pbf.read_bytes()[: pbf.stat().st_size // 2])
    with pytest.raises(CityMapError, match="truncated"):
        read_osm(cut, center=(37.8076, -122.3004))
    gz = tmp_path / "cut.osm.gz"
    whole = gzip.compress((RAW / "west-oakland.osm").read_bytes(), mtime=0)
    gz.write_bytes(whole[: len(whole) // 2])
    with pytest.raises(CityMapError, match="truncated"):
        read_osm(gz)


def test_decompression_bombs_are_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("navverse.city.osm.files._RATIO_FREE", 0)  # the ratio applies from the first byte
    bomb = tmp_path / "bomb.osm.gz"
    bomb.write_bytes(gzip.compress(b"<?xml version='1.0'?>\n<osm>" + b" " * 2_000_000 + b"</osm>\n"))
    with pytest.raises(CityMapError, match="decompression bomb"):
        read_osm(bomb)
    monkeypatch.setattr("navverse.city.osm.files.MAX_RATIO", 1)
    pbf = _to_pbf(RAW / "west-oakland.osm", tmp_path / "w.osm.pbf")
    with pytest.raises(CityMapError, match="decompression bomb"):
        read_osm(pbf, center=(37.8076, -122.3004))


def test_damaged_pbf_block_header_is_refused(tmp_path: Path) -> None:
    data = _to_pbf(RAW / "west-oakland.osm", tmp_path / "w.osm.pbf").read_bytes()
    header_length = int.from_bytes(data[:4], "big")
    header = data[4 : 4 + header_length]
    assert header[-2] == 0x18  # its last field is the block's size, a one-byte number in this file
    second = 4 + header_length + header[-1]
    damaged = tmp_path / "d.osm.pbf"
    damaged.write_bytes(data[:second] + b"\xff\xff\xff\xff" + data[second + 4 :])  # the next header's length
    with pytest.raises(CityMapError, match="not a valid PBF file"):
        read_osm(damaged, center=(37.8076, -122.3004))


def test_entity_expansion_is_refused_before_parsing(tmp_path: Path) -> None:
    bomb = (
        '<?xml version="1.0"?>\n<!DOCTYPE osm [\n <!ENTITY a "aaaaaaaaaa">\n'
        ' <!ENTITY b "&a;&a;&a;&a;&a;">\n]>\n'
        '<osm version="0.6"><node id="1" lat="48" lon="11"><tag k="name" v="&b;"/></node></osm>\n'
    )
    with pytest.raises(CityMapError, match="DOCTYPE"):
        read_osm(_write(tmp_path / "bomb.osm", bomb))
    hidden = "<?xml version='1.0'?>\n<!-- padding -->\n<!DOCTYPE osm SYSTEM 'x.dtd'>\n<osm/>\n"
    with pytest.raises(CityMapError, match="DOCTYPE"):
        read_osm(_write(tmp_path / "hidden.osm", hidden))
    long_prolog = "<?xml version='1.0'?>\n<!--" + "x" * PROLOG_LIMIT + "-->\n<osm/>\n"
    with pytest.raises(CityMapError, match="no <osm> root element"):
        read_osm(_write(tmp_path / "long.osm", long_prolog))
    gz = tmp_path / "bomb.osm.gz"
    gz.write_bytes(gzip.compress(bomb.encode()))
    with pytest.raises(CityMapError, match="DOCTYPE"):
        read_osm(gz)


def test_files_are_read_by_their_content_whatever_their_name(tmp_path: Path) -> None:
    """Overpass's ``.osm.xml.gz``, bzip2, a wrong suffix and a link named anything read the same map."""
    center = (48.0, 11.0)  # PBF written by osmium keeps no <bounds>
    expected = read_osm(T_JUNCTION, center=center)
    xml = T_JUNCTION.read_bytes()
    pbf = _to_pbf(T_JUNCTION, tmp_path / "t.osm.pbf").read_bytes()
    files = {
        "overpass.osm.xml.gz": gzip.compress(xml, mtime=0),
        "two-members.osm.gz": gzip.compress(xml[:100], mtime=0) + gzip.compress(xml[100:], mtime=0),
        "map.osm.bz2": bz2.compress(xml),
        "x.osm.pbf": xml,  # XML under a PBF name
        "y.osm": pbf,  # PBF under an XML name
        "export.xml": xml,
        "data": gzip.compress(xml, mtime=0),
    }
    for name, content in files.items():
        path = tmp_path / name
        path.write_bytes(content)
        city = read_osm(path, center=center)
        assert [r.centerline for r in city.roads] == [r.centerline for r in expected.roads], name
    link = tmp_path / "link.osm.gz"
    link.symlink_to(tmp_path / "data")
    assert len(read_osm(link, center=center).roads) == len(expected.roads)
    with pytest.raises(CityMapError, match=r"not an OSM file .*give OSM XML"):
        read_osm(_write(tmp_path / "notes.osm", "just words\n"))
    with pytest.raises(CityMapError, match="gzip but does not hold OSM XML"):
        (tmp_path / "words.osm.gz").write_bytes(gzip.compress(b"just words"))
        read_osm(tmp_path / "words.osm.gz")
    truncated = tmp_path / "cut.osm.bz2"
    truncated.write_bytes(bz2.compress(xml)[:-40])
    with pytest.raises(CityMapError, match=r"truncated|damaged"):
        read_osm(truncated)
    not_osm = _write(tmp_path / "page.osm", "<html><body/></html>\n")
    with pytest.raises(CityMapError, match="root element is <html>"):
        read_osm(not_osm)
    with pytest.raises(CityMapError, match="is empty"):
        read_osm(_write(tmp_path / "empty.osm", ""))


@pytest.mark.parametrize(
    ("body", "what"),
    [
        ('<node id="abc" lat="48" lon="11"/>', "illegal id"),
        ('<node id="1" lat="x" lon="11"/>', "coordinate"),
        ('<node id="1" lat="48" lon="11"/><way id="5"><nd ref="zz"/></way>', "illegal id"),
        ('<node id="1" lat="48" lon="11">', "not well-formed|mismatched|no element"),
    ],
)
def test_malformed_objects_are_a_clear_error(body: str, what: str, tmp_path: Path) -> None:
    path = _write(tmp_path / "bad.osm", f'<?xml version="1.0"?>\n<osm version="0.6">\n{body}\n</osm>\n')
    with pytest.raises(CityMapError, match=f"bad.osm .*({what})"):
        read_osm(path, center=(48.0, 11.0))


def test_only_regular_files_are_read(tmp_path: Path) -> None:
    with pytest.raises(CityMapError, match="does not exist"):
        read_osm(tmp_path / "missing.osm")
    fifo = tmp_path / "pipe.osm"
    os.mkfifo(fifo)
    with pytest.raises(CityMapError, match="not a regular file"):
        read_osm(fifo)


def test_window_outside_the_data_names_both(tmp_path: Path) -> None:
    with pytest.raises(CityMapError, match=r"does not meet the data of t_junction\.osm") as error:
        read_osm(T_JUNCTION, center=(48.1, 11.0))
    assert "lat 47.999000..48.001000" in str(error.value)  # the file's bounds
    assert "lat 48.095386..48.104613" in str(error.value)  # the window's


def test_window_outside_data_without_declared_bounds(tmp_path: Path) -> None:
    pbf = _to_pbf(T_JUNCTION, tmp_path / "t.osm.pbf")  # the writer declares no bounds
    centred = read_osm(pbf, size_m=(200.0, 200.0))  # without a centre: centred on where the data is
    assert len(centred.buildings) == 3
    assert abs(centred.frame.origin_lat - 48.0) < 5e-4 and abs(centred.frame.origin_lon - 11.0) < 5e-4
    with pytest.raises(CityMapError, match="does not meet the data"):
        read_osm(pbf, center=(48.1, 11.0))
    assert len(read_osm(pbf, center=(48.0, 11.0), size_m=(200.0, 200.0)).buildings) == 3


def test_bad_window_arguments_are_refused() -> None:
    with pytest.raises(CityMapError, match="not both"):
        read_osm(T_JUNCTION, center=(48.0, 11.0), bbox=(47.9, 10.9, 48.1, 11.1))
    with pytest.raises(CityMapError, match="size_m"):
        read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(0.0, 100.0))
    with pytest.raises(CityMapError, match="UTM range"):
        read_osm(T_JUNCTION, center=(89.0, 11.0))
    with pytest.raises(CityMapError, match="min < max"):
        read_osm(T_JUNCTION, bbox=(48.1, 10.9, 47.9, 11.1))
    with pytest.raises(CityMapError, match="seed"):
        read_osm(T_JUNCTION, seed=-1)
    with pytest.raises(CityMapError, match="two numbers"):
        read_osm(T_JUNCTION, center="48")
    with pytest.raises(CityMapError, match="four numbers"):
        read_osm(T_JUNCTION, bbox="1234")


def test_no_roads_or_buildings_is_an_error(tmp_path: Path) -> None:
    park = _osm_xml(
        {1: (0, 0, {}), 2: (30, 0, {}), 3: (30, 30, {}), 4: (0, 30, {}), 5: (10, 10, {"natural": "tree"})},
        {10: ([1, 2, 3, 4, 1], {"leisure": "park"})},
    )
    with pytest.raises(CityMapError, match="no roads or buildings in the window"):
        read_osm(_write(tmp_path / "park.osm", park), center=(48.0, 11.0))


def test_messy_data_is_repaired_or_dropped_and_counted(tmp_path: Path) -> None:
    nodes = {i: (x, y, {}) for i, (x, y) in enumerate([(-50, 0), (0, 0), (50, 0), (60, 10)], start=1)}
    nodes |= {11: (10, 10, {}), 12: (30, 30, {}), 13: (30, 10, {}), 14: (10, 30, {})}  # a bow-tie
    nodes |= {21: (-40, 10, {}), 22: (-20, 10, {}), 23: (-20, 30, {}), 24: (-40, 30, {})}
    ways = {
        100: ([1, 2, 999, 3, 4], {"highway": "residential", "width": "wide", "lanes": "two"}),
        101: ([1, 888], {"highway": "service"}),  # one node left: nothing to keep
        102: ([2, 3], {"highway": "primary", "tunnel": "yes"}),
        110: ([11, 12, 13, 14, 11], {"building": "yes", "height": "tall"}),  # self-intersecting
        111: ([21, 22, 23, 24, 21], {"building": "yes"}),
        112: ([21, 22, 23, 24, 21], {"building:part": "yes", "height": "6"}),
        113: ([21, 22, 23], {"building": "yes"}),  # not closed
    }
    text = _osm_xml(nodes, ways)
    duplicate = '  <way id="111">\n    <nd ref="21"/>\n    <nd ref="22"/>\n    <nd ref="23"/>\n'
    duplicate += '    <nd ref="21"/>\n    <tag k="building" v="yes"/>\n  </way>\n'
    text = text.replace("</osm>", duplicate + "</osm>")  # the same way id again
    city = read_osm(_write(tmp_path / "messy.osm", text), center=(48.0, 11.0), size_m=(200.0, 200.0))

    # the primary is in a tunnel; the service road has one node left; the residential road is split
    # where its missing node was: 1-2 and 3-4
    west, east = city.roads
    assert west.osm == east.osm == "way/100"
    assert west.width_source == "default" and west.lanes is None
    assert west.centerline.length == pytest.approx(50.0, abs=0.05)
    assert east.centerline.length == pytest.approx(math.hypot(10, 10), abs=0.05)
    bowtie = [b for b in city.buildings if b.osm == "way/110"]
    assert len(bowtie) == 2 and all(b.height_source == "drawn" for b in bowtie)  # two triangles
    assert sum(_area(b.footprint) for b in bowtie) == pytest.approx(200.0, rel=0.02)
    # The building stands as its one part, which covers the whole outline: not counted twice.
    (part,) = [b for b in city.buildings if b.osm != "way/110"]
    assert (part.osm, part.outline, part.height, part.height_source) == ("way/112", "way/111", 6.0, "height")
    assert city.dropped == {
        "building or area way that is not a closed ring": 1,
        "duplicate OSM object (one copy kept)": 1,
        "invalid polygon (self-intersecting or overlapping rings; repaired)": 1,
        "road not at ground level (tunnel, layer or level < 0)": 1,
        "tag height not read cleanly (a rule or its first value used)": 1,
        "tag lanes not read cleanly (a rule or its first value used)": 1,
        "tag width not read cleanly (a rule or its first value used)": 1,
        "way with missing nodes (kept the parts between them)": 1,
        "way with missing nodes (too few nodes left; dropped)": 1,
    }


def test_negative_ids_of_editor_files_are_counted_not_fatal(tmp_path: Path) -> None:
    nodes = {-1: (0, 0, {}), -2: (30, 0, {}), -3: (30, 30, {}), 1: (-50, -5, {}), 2: (50, -5, {})}
    ways = {-10: ([-1, -2, -3, -1], {"building": "yes"}), 5: ([1, 2], {"highway": "residential"})}
    relations = {-20: ([("way", -10, "outer")], {"type": "multipolygon", "landuse": "grass"})}
    path = _write(tmp_path / "josm.osm", _osm_xml(nodes, ways, relations))
    city = read_osm(path, center=(48.0, 11.0))
    assert [r.osm for r in city.roads] == ["way/5"]
    assert city.dropped == {"way whose nodes are all missing (anywhere in the file)": 1}


def test_nodes_and_relations_given_twice_keep_one_copy(tmp_path: Path) -> None:
    nodes = {1: (0, 0, {}), 2: (30, 0, {}), 3: (30, 30, {}), 4: (0, 30, {}), 5: (5, 5, {"shop": "bakery"})}
    ways = {10: ([1, 2, 3, 4, 1], {})}
    relations = {20: ([("way", 10, "outer")], {"type": "multipolygon", "building": "yes"})}
    text = _osm_xml(nodes, ways, relations)
    node = text[text.index('  <node id="5"') : text.index("</node>", text.index('<node id="5"')) + 8]
    relation = text[text.index("  <relation") : text.index("</relation>") + 12]
    text = text.replace(node, node + node).replace(relation, relation + relation)
    city = read_osm(_write(tmp_path / "twice.osm", text), center=(48.0, 11.0))
    assert [b.osm for b in city.buildings] == ["relation/20"]
    assert [(p.osm, p.building) for p in city.pois] == [("node/5", city.buildings[0].id)]
    assert city.dropped == {"duplicate OSM object (one copy kept)": 2}


def test_duplicate_outline_of_a_multipolygon_is_dropped(tmp_path: Path) -> None:
    nodes = {1: (0, 0, {}), 2: (30, 0, {}), 3: (30, 30, {}), 4: (0, 30, {})}
    ways = {10: ([1, 2, 3, 4, 1], {"building": "yes"})}
    relations = {20: ([("way", 10, "outer")], {"type": "multipolygon", "building": "yes", "height": "7"})}
    city = read_osm(_write(tmp_path / "old.osm", _osm_xml(nodes, ways, relations)), center=(48.0, 11.0))
    (building,) = city.buildings
    assert (building.osm, building.height) == ("relation/20", 7.0)
    assert city.dropped == {"way repeating its multipolygon's outline (the multipolygon is kept)": 1}


def test_oneway_against_the_way_is_turned_and_parking_read(tmp_path: Path) -> None:
    nodes = {1: (-40, 0, {}), 2: (40, 0, {})}
    tags = {"highway": "residential", "oneway": "-1", "sidewalk": "left", "parking:right": "lane"}
    city = read_osm(_write(tmp_path / "one.osm", _osm_xml(nodes, {10: ([1, 2], tags)})), center=(48.0, 11.0))
    (road,) = city.roads
    assert road.oneway and road.centerline.points[0][0] > road.centerline.points[-1][0]  # east to west
    assert (road.sidewalk_left, road.sidewalk_right) == (None, 1.5)  # sides turn with the line
    assert (road.parking_left, road.parking_right) == (2.0, None)


def _town(path: Path, blocks: range, *, reverse: bool = False) -> Path:
    """A row of untagged 10 m × 10 m buildings, one per block, way ids 1000 + block."""
    nodes, ways = {}, {}
    for k in blocks:
        x, base = -90 + 15 * k, 100 * (k + 1)
        nodes |= {base + 1: (x, 0, {}), base + 2: (x + 10, 0, {}), base + 3: (x + 10, 10, {})}
        nodes[base + 4] = (x, 10, {})
        ways[1000 + k] = ([base + 1, base + 2, base + 3, base + 4, base + 1], {"building": "yes"})
    if reverse:
        ways = dict(reversed(list(ways.items())))
    return _write(path, _osm_xml(nodes, ways))


def _heights(path: Path, seed: int) -> dict[str, float]:
    city = read_osm(path, center=(48.0, 11.0), size_m=(200.0, 200.0), seed=seed)
    assert city.source.seed == seed
    assert all(b.height_source == "drawn" and b.levels == b.height / 3.0 for b in city.buildings)
    return {b.osm: b.height for b in city.buildings}


def test_untagged_heights_depend_on_seed_and_object_only(tmp_path: Path) -> None:
    town = _heights(_town(tmp_path / "town.osm", range(12)), 7)
    assert set(town.values()) == {3.0, 6.0, 9.0}  # 1-3 storeys of 3 m
    assert _heights(_town(tmp_path / "half.osm", range(0, 12, 2)), 7) == {
        osm: h for osm, h in town.items() if int(osm.split("/")[1]) % 2 == 0
    }
    assert _heights(_town(tmp_path / "town.osm", range(12)), 8) != town


def test_unsorted_file_is_sorted_in_memory(tmp_path: Path) -> None:
    town = _heights(_town(tmp_path / "town.osm", range(12)), 7)
    assert _heights(_town(tmp_path / "nwot.osm", range(12), reverse=True), 7) == town


def test_unsorted_file_too_large_to_sort_says_how(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("navverse.city.osm.stream.MAX_SORT_BYTES", 0)
    path = _town(tmp_path / "nwot.osm", range(3), reverse=True)
    with pytest.raises(
        CityMapError, match=r"too large to sort in memory: sort it first, e\.g\. `osmium sort"
    ):
        read_osm(path, center=(48.0, 11.0))


def test_large_files_keep_node_locations_on_disk(junction: CityMap, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("navverse.city.osm.stream.IN_MEMORY_INDEX_NODES", 0)
    on_disk = read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))
    assert on_disk == junction


# Tag tables and geometry helpers -----------------------------------------------------------------


def test_tag_tables() -> None:
    from collections import Counter

    dropped: Counter[str] = Counter()
    assert kerb_of(None, dropped, default="lowered") == "lowered"
    assert kerb_of("no", dropped, default="lowered") == "flush"
    assert kerb_of("weird", dropped, default="lowered") == "lowered"
    assert dropped == {"unknown kerb value (default used)": 1}
    assert land_class({"natural": "water", "leisure": "park"}, relation=False) == "water"
    assert land_class({"highway": "pedestrian"}, relation=False) is None
    assert land_class({"highway": "pedestrian", "area": "yes"}, relation=False) == "plaza"
    assert land_class({"amenity": "parking", "parking": "underground"}, relation=False) is None
    assert land_class({"leisure": "park", "building": "yes"}, relation=False) is None
    assert poi_of({"amenity": "cafe", "shop": "bakery"}) == ("cafe", "amenity=cafe")
    assert poi_of({"amenity": "parking", "shop": "bakery"}) == ("bakery", "shop=bakery")
    assert poi_of({"amenity": "school"}) == ("school", "amenity=school")
    assert poi_of({"office": "yes"}) == ("office", "office=yes")
    assert poi_of({"amenity": "bench"}) is None
    assert walkway_kind({"highway": "footway", "footway": "sidewalk"}) == "sidewalk"
    assert walkway_kind({"highway": "steps"}) == "steps"
    assert walkway_kind({"highway": "residential"}) is None
    assert parking_sides({"parking:lane:both": "diagonal"}, dropped) == (4.5, 4.5)
    assert parking_sides({"parking:both": "lane", "parking:left:orientation": "perpendicular"}, dropped) == (
        5.0,
        2.0,
    )
    assert parking_sides({"parking:both": "no", "parking:lane:both": "parallel"}, dropped) == (None, None)
    assert parking_sides({"parking:right": "lane", "parking:right:width": "2.5"}, dropped) == (None, 2.5)
    tags = {"building": "house"}
    draws = {drawn_storeys(tags, seed=1, osm_type="way", osm_id=i) for i in range(40)}
    assert draws == {1, 2}
    assert drawn_storeys(tags, seed=1, osm_type="way", osm_id=-5) in (1, 2)
    assert utm_epsg(48.0, 11.0) == 32632 and utm_epsg(-33.9, 18.4) == 32734 and utm_epsg(0.0, 180.0) == 32660


@pytest.mark.parametrize(
    ("tags", "markings"),
    [
        ({}, "zebra"),
        ({"crossing:markings": "no"}, "none"),
        ({"crossing:markings": " Yes "}, "zebra"),
        ({"crossing:markings": "zebra:bicolour"}, "zebra"),
        ({"crossing:markings": "lines"}, "lines"),
        ({"crossing:markings": "lines:paired"}, "lines"),
        ({"crossing:markings": "LINES:dashed"}, "dashes"),
        ({"crossing:markings": "ladder:skewed"}, "ladder"),
        ({"crossing:markings": "dots"}, "dashes"),
        ({"crossing:markings": "surface", "crossing": "zebra"}, "none"),  # markings win
        ({"crossing:markings": "pictograms"}, "none"),
        ({"crossing_ref": "pelican", "crossing": "traffic_signals"}, "dashes"),
        ({"crossing_ref": "Zebra"}, "zebra"),
        ({"crossing_ref": "tiger", "crossing": "unmarked"}, "none"),  # an unknown ref falls through
        ({"crossing": "traffic_signals"}, "lines"),
        ({"crossing": "uncontrolled"}, "zebra"),
        ({"crossing": "informal"}, "zebra"),
    ],
)
def test_crossing_markings_by_tag(tags: dict[str, str], markings: str) -> None:
    from collections import Counter

    dropped: Counter[str] = Counter()
    assert crossing_markings(tags, dropped) == markings
    assert not dropped


def test_unknown_crossing_markings_are_counted_and_the_other_tags_read() -> None:
    from collections import Counter

    dropped: Counter[str] = Counter()
    assert (
        crossing_markings({"crossing:markings": "rainbow", "crossing": "traffic_signals"}, dropped) == "lines"
    )
    assert dropped == {"unknown crossing:markings value (other crossing tags used)": 1}


def test_crossing_nodes_read_their_markings(tmp_path: Path) -> None:
    nodes = {
        1: (-60.0, 0.0, {}),
        2: (-30.0, 0.0, {"highway": "crossing", "crossing": "traffic_signals"}),
        3: (0.0, 0.0, {"highway": "crossing", "crossing": "uncontrolled", "crossing:markings": "no"}),
        4: (30.0, 0.0, {"highway": "crossing", "crossing:markings": "odd"}),
        5: (60.0, 0.0, {}),
    }
    text = _osm_xml(nodes, {10: ([1, 2, 3, 4, 5], {"highway": "residential"})})
    city = read_osm(_write(tmp_path / "crossings.osm", text), center=(48.0, 11.0), size_m=(200.0, 200.0))
    by_node = {c.osm: c.markings for c in city.crossings}
    assert by_node == {"node/2": "lines", "node/3": "none", "node/4": "zebra"}
    assert city.dropped["unknown crossing:markings value (other crossing tags used)"] == 1


def test_clip_polyline_keeps_direction_and_closed_loops() -> None:
    rect = (-10.0, -10.0, 10.0, 10.0)
    line = np.array([[20.0, 0.0], [0.0, 0.0], [-20.0, 0.0]])
    (piece,) = clip_polyline(line, rect)
    assert piece.tolist() == [[10.0, 0.0], [0.0, 0.0], [-10.0, 0.0]]
    loop = np.array([[0.0, 0.0], [5.0, 0.0], [5.0, 5.0], [0.0, 0.0]])
    (piece,) = clip_polyline(loop, rect)
    assert piece.tolist() == loop.tolist()
    zigzag = np.array([[-5.0, 0.0], [-5.0, 20.0], [5.0, 20.0], [5.0, 0.0]])
    assert [p.tolist() for p in clip_polyline(zigzag, rect)] == [
        [[-5.0, 0.0], [-5.0, 10.0]],
        [[5.0, 10.0], [5.0, 0.0]],
    ]
    assert clip_polyline(np.array([[20.0, 20.0], [30.0, 30.0]]), rect) == []


def test_a_bus_stop_keeps_its_shelter_tag(tmp_path: Path) -> None:
    nodes = {
        1: (-50.0, 0.0, {}),
        2: (50.0, 0.0, {}),
        3: (0.0, 8.0, {"highway": "bus_stop", "shelter": "yes"}),
        4: (20.0, 8.0, {"highway": "bus_stop"}),
    }
    text = _osm_xml(nodes, {10: ([1, 2], {"highway": "residential"})})
    city = read_osm(_write(tmp_path / "stops.osm", text), center=(48.0, 11.0), size_m=(200.0, 200.0))
    assert sorted((f.kind, f.shelter) for f in city.furniture) == [("bus_stop", False), ("bus_stop", True)]


def test_schools_are_places(tmp_path: Path) -> None:
    nodes = {
        1: (-50.0, 0.0, {}),
        2: (50.0, 0.0, {}),
        3: (0.0, 20.0, {"amenity": "school", "name": "Grundschule"}),
        4: (20.0, 20.0, {"amenity": "kindergarten"}),
    }
    text = _osm_xml(nodes, {10: ([1, 2], {"highway": "residential"})})
    city = read_osm(_write(tmp_path / "school.osm", text), center=(48.0, 11.0), size_m=(200.0, 200.0))
    assert sorted(p.category for p in city.pois) == ["kindergarten", "school"]


def test_building_passages_are_freed_at_ground_level_under_the_building(tmp_path: Path) -> None:
    # A 20 m deep front building on a street; a driveway through it (its end nodes 0.5 m short of
    # both walls, as mappers often leave them), a 3 m high one-storey shed the same driveway runs
    # on under, and an underground footway (a plain tunnel) that stays out.
    nodes = {
        1: (0, 0, {}),
        2: (40, 0, {}),
        3: (40, 20, {}),
        4: (0, 20, {}),  # front building, 12 m
        5: (0, 30, {}),
        6: (40, 30, {}),
        7: (40, 36, {}),
        8: (0, 36, {}),  # shed, 3 m
        11: (20, 0.5, {}),
        12: (20, 19.5, {}),
        13: (20, 40, {}),  # the passage and on
        21: (-20, -5, {}),
        22: (60, -5, {}),  # the street
        31: (5, -3, {}),
        32: (5, 25, {}),  # a tunnel under the building
    }
    passage = {
        "highway": "service",
        "tunnel": "building_passage",
        "layer": "-1",
        "width": "3",
        "maxheight": "4.2",
    }
    ways = {
        100: ([1, 2, 3, 4, 1], {"building": "yes", "height": "12"}),
        101: ([5, 6, 7, 8, 5], {"building": "shed", "height": "3"}),
        102: ([11, 12], passage),
        103: ([12, 13], {"highway": "service", "covered": "yes", "width": "3"}),
        104: ([21, 22], {"highway": "residential"}),
        105: ([31, 32], {"highway": "footway", "tunnel": "yes"}),
    }
    city = read_osm(_write(tmp_path / "passage.osm", _osm_xml(nodes, ways)), center=(48.0, 11.0))
    assert sorted(r.osm for r in city.roads) == ["way/102", "way/103", "way/104"]
    assert city.walkways == []  # the tunnel is underground: left out
    front = [b for b in city.buildings if b.osm == "way/100"]
    over = [b for b in front if b.base_height > 0.0]
    assert len(over) == 1 and (over[0].base_height, over[0].height) == (4.2, 12.0)  # maxheight
    standing = shapely.union_all([_shape(b) for b in front if b.base_height == 0.0])
    corridor = LineString([(20, -1), (20, 21)]).buffer(1.4, cap_style="flat")  # wall to wall
    assert standing.intersection(corridor).area < 0.01 and abs(standing.area - 800 + 60) < 0.5
    assert abs(_shape(over[0]).area - 60) < 0.5
    shed = [_shape(b) for b in city.buildings if b.osm == "way/101"]
    assert abs(sum(s.area for s in shed) - 240 + 18) < 0.5  # too low to span the way: open over it
    assert (
        city.dropped["building raised over a passage at ground level (tunnel=building_passage, covered)"] == 1
    )
    assert city.dropped["building left open over a passage (lower than the passage's headroom)"] == 1


def test_cycle_tracks_lie_between_the_carriageway_and_the_sidewalk(tmp_path: Path) -> None:
    nodes = {
        1: (-60, 0, {}),
        2: (60, 0, {}),
        3: (-60, 40, {}),
        4: (60, 40, {}),
        5: (-60, 46.2, {}),
        6: (60, 46.2, {}),
    }
    nodes |= {7: (-60, -40, {}), 8: (60, -40, {})}
    ways = {
        10: ([1, 2], {"highway": "residential", "width": "7", "sidewalk": "both", "cycleway:right": "track",
                      "cycleway:right:width": "2"}),
        11: ([3, 4], {"highway": "residential", "width": "7", "sidewalk": "both", "cycleway": "track"}),
        12: ([5, 6], {"highway": "cycleway"}),  # the track on way 11's left, mapped on its own too
        13: ([7, 8], {"highway": "residential", "width": "4", "oneway": "-1", "sidewalk": "no",
                      "cycleway": "track"}),
    }  # fmt: skip
    city = read_osm(_write(tmp_path / "tracks.osm", _osm_xml(nodes, ways)), center=(48.0, 11.0))
    roads = {r.osm: r for r in city.roads}
    assert (roads["way/10"].cycle_track_left, roads["way/10"].cycle_track_right) == (None, 2.0)
    assert (roads["way/11"].cycle_track_left, roads["way/11"].cycle_track_right) == (None, 1.8)
    assert (
        city.dropped["cycle track of the road's tags left out (a mapped cycleway runs beside the road)"] == 1
    )
    one_way = roads["way/13"]  # traffic runs west, so the points are turned to follow it: its track on
    # the right of the traffic, to the north
    assert one_way.centerline.points[0][0] > 0 and (one_way.cycle_track_left, one_way.cycle_track_right) == (
        None,
        1.8,
    )
    plan = geometry_plan(city, CityGeometry())
    walked = shapely.union_all([plan.classes["sidewalk"], plan.classes["curb"]])
    # Way 10: 3.5 m of carriageway, then 2 m of track and 1.5 m of sidewalk behind the curb on the
    # right (y < 0); 1.5 m of sidewalk on the left.
    right = walked.intersection(LineString([(0, -3.4), (0, -8.0)])).length
    left = walked.intersection(LineString([(0, 3.4), (0, 8.0)])).length
    assert abs(right - 3.5) < 0.05 and abs(left - 1.5) < 0.05
    assert plan.classes["curb"].intersection(LineString([(0, -3.4), (0, -3.8)])).length > 0.1
    # Way 13 has no sidewalk: its track alone is a raised strip behind a curb.
    assert abs(walked.intersection(LineString([(0, -38.1), (0, -35.0)])).length - 1.8) < 0.05
    assert walked.intersection(LineString([(0, -41.9), (0, -45.0)])).is_empty
    assert _without_source(read_city_map(write_city_map(city, tmp_path / "map.json"))) == _without_source(
        city
    )
