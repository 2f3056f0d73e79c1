"""The city map contract: validation, references, and byte-stable round trips."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from pydantic import ValidationError

from navverse.city.map import (
    Building,
    CityMap,
    CityMapError,
    Crossing,
    Frame,
    LandArea,
    Path2,
    Poi,
    Polygon2,
    Road,
    read_city_map,
    write_city_map,
)


def _square(x: float, y: float, side: float) -> Polygon2:
    return Polygon2(exterior=[(x, y), (x + side, y), (x + side, y + side), (x, y + side)])


def _city(**overrides) -> CityMap:
    road = Road(
        id="road-1",
        osm="way/42",
        highway="residential",
        centerline=Path2(points=[(0.0, 0.0), (100.0, 0.0)]),
        width=6.5,
        width_source="default",
        sidewalk_left=1.5,
        sidewalk_right=1.5,
    )
    fields = {
        "source": {"kind": "osm", "name": "t.osm", "sha256": "0" * 64, "attribution": "© OSM contributors"},
        "frame": Frame(epsg=32633, origin_lat=48.2, origin_lon=16.4),
        "window": (-50.0, -50.0, 150.0, 150.0),
        "roads": [road],
        "crossings": [Crossing(id="crossing-1", osm="node/7", position=(50.0, 0.0), road="road-1")],
        "areas": [LandArea(id="area-1", cls="green", polygon=_square(0, 20, 30))],
        "buildings": [
            Building(
                id="building-1",
                osm="way/9",
                footprint=Polygon2(
                    exterior=[(40.0, 10.0), (80.0, 10.0), (80.0, 40.0), (40.0, 40.0)],
                    holes=[[(50.0, 20.0), (60.0, 20.0), (60.0, 30.0)]],
                ),
                height=12.0,
                height_source="levels",
                levels=4,
            )
        ],
        "pois": [
            Poi(id="poi-1", position=(45.0, 10.0), category="cafe", tag="amenity=cafe", building="building-1")
        ],
        "dropped": {"way without nodes": 2},
    }
    fields.update(overrides)
    return CityMap(**fields)


def test_a_map_round_trips_to_the_same_bytes(tmp_path: Path):
    city = _city()
    first = write_city_map(city, tmp_path / "a.json").read_bytes()
    again = read_city_map(tmp_path / "a.json")
    assert again == city
    assert write_city_map(again, tmp_path / "b.json").read_bytes() == first
    assert json.loads(first)["areas"][0]["class"] == "green"


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"window": (10.0, 0.0, 0.0, 5.0)}, "min < max"),
        ({"crossings": [Crossing(id="crossing-1", position=(1.0, 1.0), road="road-9")]}, "lacks"),
        (
            {"pois": [Poi(id="road-1", position=(1.0, 1.0), category="cafe", tag="amenity=cafe")]},
            "used twice",
        ),
    ],
)
def test_broken_maps_are_refused(change, message):
    with pytest.raises(ValidationError, match=message):
        _city(**change)


def test_features_refuse_degenerate_and_non_finite_geometry():
    with pytest.raises(ValidationError, match="3 distinct points"):
        Polygon2(exterior=[(0.0, 0.0), (1.0, 0.0), (0.0, 0.0)])
    with pytest.raises(ValidationError, match="written open"):
        Polygon2(exterior=[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 0.0)])
    with pytest.raises(ValidationError, match="two distinct points"):
        Path2(points=[(1.0, 1.0), (1.0, 1.0)])
    with pytest.raises(ValidationError):
        Path2(points=[(0.0, 0.0), (float("nan"), 1.0)])
    with pytest.raises(ValidationError, match="above base_height"):
        Building(
            id="building-2", footprint=_square(0, 0, 5), height=3.0, base_height=3.0, height_source="height"
        )


def test_a_bad_file_is_a_city_map_error(tmp_path: Path):
    with pytest.raises(CityMapError, match="does not exist"):
        read_city_map(tmp_path / "none.json")
    (tmp_path / "x.json").write_text("{")
    with pytest.raises(CityMapError, match="not a city map JSON"):
        read_city_map(tmp_path / "x.json")
    data = _city().model_dump(mode="json", by_alias=True)
    (tmp_path / "v.json").write_text(json.dumps({**data, "format_version": "2.0"}))
    with pytest.raises(CityMapError, match=r"format 2\.0.*rebuild the city"):
        read_city_map(tmp_path / "v.json")
    data["roads"][0]["width"] = -1
    (tmp_path / "w.json").write_text(json.dumps(data))
    with pytest.raises(CityMapError, match=r"roads\.0\.width"):
        read_city_map(tmp_path / "w.json")


def test_path_length():
    assert Path2(points=[(0.0, 0.0), (3.0, 4.0), (3.0, 10.0)]).length == pytest.approx(11.0)


def test_a_format_1_3_map_reads_with_zebra_crossings(tmp_path: Path):
    city = _city(crossings=[Crossing(id="crossing-1", position=(50.0, 0.0), road="road-1", markings="lines")])
    old = city.model_dump(mode="json", by_alias=True)
    for crossing in old["crossings"]:
        del crossing["markings"]
    (tmp_path / "old.json").write_text(json.dumps({**old, "format_version": "1.3"}))
    (crossing,) = read_city_map(tmp_path / "old.json").crossings
    assert crossing.markings == "zebra"
    with pytest.raises(ValidationError, match="markings"):
        Crossing(id="crossing-2", position=(1.0, 1.0), road="road-1", markings="stripes")
