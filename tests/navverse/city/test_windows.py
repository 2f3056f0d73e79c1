"""``navverse city windows``: the windows of an OSM file ranked by buildings, POIs and streets.

The ranking (:mod:`navverse.city.osm.windows`) on a hand-laid file whose counts are known, on real
extracts (dense old towns above their edges, a file without bounds, gzip XML, data smaller than a
window), against what the reader finds in the same window; the command's table, the recipe it prints
(saved, it validates) and the commands after it, its thumbnails, and its one-line errors.
"""

from __future__ import annotations

import bz2
import math
import re
import shlex
import struct
from pathlib import Path

import pytest
from pyproj import Transformer
from shapely.geometry import LineString

from navverse import cli
from navverse.city.map import CityMapError
from navverse.city.osm import stream as stream_module
from navverse.city.osm import windows as windows_module
from navverse.city.osm.reader import read_osm
from navverse.city.osm.window import utm_epsg
from navverse.city.osm.windows import MIN_SCORE, WindowRanking, rank_windows
from navverse.commands.workspace import write_workspace

RAW = Path(__file__).parents[3] / "data" / "raw" / "osm"
MUNICH = RAW / "munich-altstadt.osm.pbf"
NYC = RAW / "nyc-lower-east-side.osm.pbf"
BERLIN = RAW / "berlin-mitte.osm.xml.gz"
NORTHGATE = RAW / "seattle-northgate.osm"  # an Overpass export: no <bounds>
KIRCHBERG = RAW / "kirchberg-an-der-iller.osm"  # 205 m x 155 m of data

# ------------------------------------------------------------------------------------ a known file

_LAT, _LON = 48.0, 11.0
_TO_LONLAT = Transformer.from_crs(f"EPSG:{utm_epsg(_LAT, _LON)}", "EPSG:4326", always_xy=True)
_ORIGIN = Transformer.from_crs("EPSG:4326", f"EPSG:{utm_epsg(_LAT, _LON)}", always_xy=True).transform(
    _LON, _LAT
)


def _square(first_id: int, x: float, y: float, side: float = 10.0) -> dict[int, tuple[float, float]]:
    return {
        first_id + k: (x + dx, y + dy)
        for k, (dx, dy) in enumerate([(0, 0), (side, 0), (side, side), (0, side)])
    }


def _known_osm(path: Path) -> Path:
    """OSM XML (meters east and north of 48 N 11 E) holding 3 buildings, 2 POIs and 250 m of streets,
    with as many look-alikes the reader leaves out."""
    nodes: dict[int, tuple[float, float, dict[str, str]]] = {}
    for first, x in ((1, 0.0), (11, 30.0), (21, 60.0), (31, 90.0)):
        nodes |= {i: (px, py, {}) for i, (px, py) in _square(first, x, 0.0).items()}
    nodes |= {
        41: (0.0, 50.0, {}), 42: (200.0, 50.0, {}),  # a road, 200 m
        43: (0.0, 80.0, {}), 44: (50.0, 80.0, {}),  # a footway, 50 m
        45: (0.0, 120.0, {}), 46: (400.0, 120.0, {}),  # a motorway in a tunnel: not a street
        47: (5.0, 20.0, {"shop": "bakery"}),  # a POI
        48: (15.0, 20.0, {"amenity": "bench"}),  # furniture, not a POI
    }  # fmt: skip
    ways = {
        101: ([1, 2, 3, 4, 1], {"building": "yes"}),
        102: ([11, 12, 13, 14, 11], {"building": "retail", "shop": "supermarket"}),  # a building and a POI
        103: ([21, 22, 23, 24, 21], {"building": "roof"}),  # open sides: not a building
        104: ([31, 32, 33, 34, 31], {}),  # the outline of the relation below
        105: ([41, 42], {"highway": "residential"}),
        106: ([43, 44], {"highway": "footway"}),
        107: ([45, 46], {"highway": "motorway", "tunnel": "yes"}),
        108: ([1, 2, 3, 4, 1], {"highway": "pedestrian", "area": "yes"}),  # a plaza, not a street
    }
    relations = {201: ([("w", 104, "outer")], {"type": "multipolygon", "building": "yes"})}
    lines = ["<?xml version='1.0' encoding='UTF-8'?>", '<osm version="0.6">']
    for node_id, (x, y, tags) in nodes.items():
        lon, lat = _TO_LONLAT.transform(_ORIGIN[0] + x, _ORIGIN[1] + y)
        lines.append(f'<node id="{node_id}" version="1" lat="{lat:.7f}" lon="{lon:.7f}">')
        lines += [f'<tag k="{k}" v="{v}"/>' for k, v in tags.items()] + ["</node>"]
    for way_id, (refs, tags) in ways.items():
        lines.append(f'<way id="{way_id}" version="1">')
        lines += [f'<nd ref="{r}"/>' for r in refs] + [f'<tag k="{k}" v="{v}"/>' for k, v in tags.items()]
        lines.append("</way>")
    for relation_id, (members, tags) in relations.items():
        lines.append(f'<relation id="{relation_id}" version="1">')
        lines += [f'<member type="{t}" ref="{r}" role="{role}"/>' for t, r, role in members]
        lines += [f'<tag k="{k}" v="{v}"/>' for k, v in tags.items()] + ["</relation>"]
    path.write_text("\n".join([*lines, "</osm>", ""]), encoding="utf-8")
    return path


def test_a_known_file_counts_what_the_reader_makes_buildings_pois_and_streets_of(tmp_path: Path):
    ranking = rank_windows(_known_osm(tmp_path / "known.osm"), size_m=1000)
    assert (ranking.buildings, ranking.pois) == (3, 2)
    assert ranking.street_m == pytest.approx(250.0, abs=0.5)
    assert ranking.bounds is None and ranking.format == "xml"
    (window,) = ranking.windows  # 200 m of data in a 1 km window: one window, the data's extent
    assert (window.buildings, window.pois, window.street_km) == (3, 2, pytest.approx(0.25, abs=1e-3))
    assert window.size_m == (220.0, 100.0)  # 200 m x 80 m of positions, 10 m more each side, rounded up
    x, y = Transformer.from_crs("EPSG:4326", f"EPSG:{utm_epsg(_LAT, _LON)}", always_xy=True).transform(
        window.center[1], window.center[0]
    )
    assert (x - _ORIGIN[0], y - _ORIGIN[1]) == (pytest.approx(100.0, abs=0.5), pytest.approx(40.0, abs=0.5))


# ------------------------------------------------------------------------------------ real extracts


def _local(ranking: WindowRanking) -> list[tuple[float, float]]:
    """The windows' centres in meters of one UTM frame."""
    lat, lon = ranking.windows[0].center
    forward = Transformer.from_crs("EPSG:4326", f"EPSG:{utm_epsg(lat, lon)}", always_xy=True)
    return [forward.transform(w.center[1], w.center[0]) for w in ranking.windows]


@pytest.mark.parametrize("path", [MUNICH, NYC], ids=["munich", "nyc"])
def test_the_dense_centre_ranks_first_and_the_windows_do_not_overlap(path: Path):
    ranking = rank_windows(path, size_m=500, top=10)
    best, last = ranking.windows[0], ranking.windows[-1]
    assert len(ranking.windows) >= 3
    assert [w.rank for w in ranking.windows] == list(range(1, len(ranking.windows) + 1))
    assert [w.score for w in ranking.windows] == sorted((w.score for w in ranking.windows), reverse=True)
    assert best.buildings > 2 * last.buildings and best.pois > 2 * last.pois
    assert min(w.score for w in ranking.windows) >= MIN_SCORE
    centres = _local(ranking)
    for a in range(len(centres)):
        for b in range(a):
            gap = max(abs(centres[a][0] - centres[b][0]), abs(centres[a][1] - centres[b][1]))
            assert gap >= 500 - 1.0, (a + 1, b + 1, gap)
    west, south, east, north = ranking.bounds
    assert all(south <= w.center[0] <= north and west <= w.center[1] <= east for w in ranking.windows)


def test_munichs_best_window_holds_marienplatz():
    best = rank_windows(MUNICH, size_m=500, top=1).windows[0]
    forward = Transformer.from_crs("EPSG:4326", "EPSG:32632", always_xy=True)
    x, y = forward.transform(best.center[1], best.center[0])
    mx, my = forward.transform(11.57548, 48.13743)  # Marienplatz
    assert max(abs(x - mx), abs(y - my)) < 250.0


def test_a_windows_counts_are_what_the_reader_reads_in_it():
    best = rank_windows(NYC, size_m=500, top=1).windows[0]
    city = read_osm(NYC, center=best.center, size_m=best.size_m)
    streets = sum(LineString(f.centerline.points).length for f in [*city.roads, *city.walkways])
    assert best.pois == pytest.approx(len(city.pois), rel=0.05)
    assert best.street_m == pytest.approx(streets, rel=0.05)
    # the reader also counts the pieces of outlines crossing the window's edge
    assert 0.85 * len(city.buildings) <= best.buildings <= len(city.buildings)


def test_a_file_without_bounds_is_ranked_on_its_data():
    ranking = rank_windows(NORTHGATE, size_m=300, top=5)
    assert ranking.bounds is None
    west, south, east, north = ranking.extent
    assert 47.70 < south < north < 47.72 and -122.34 < west < east < -122.31
    assert ranking.windows[0].buildings >= 15 and ranking.windows[0].street_km > 3.0
    assert all(south <= w.center[0] <= north and west <= w.center[1] <= east for w in ranking.windows)


def test_gzip_xml_is_read_and_the_ranking_is_the_same_each_time():
    first = rank_windows(BERLIN, size_m=500, top=5)
    assert first.format == "xml.gz" and first.bounds is None
    assert first.buildings > 1500 and first.street_m > 150_000
    assert first.windows[0].buildings > 250 and first.windows[0].pois > 250
    assert rank_windows(BERLIN, size_m=500, top=5) == first


def test_the_format_and_name_do_not_change_the_ranking_nor_an_index_on_disk(tmp_path, monkeypatch):
    expected = rank_windows(NORTHGATE, size_m=200, top=4)
    packed = tmp_path / "northgate.data"  # bzip2 XML named anything
    packed.write_bytes(bz2.compress(NORTHGATE.read_bytes()))
    monkeypatch.setattr(stream_module, "IN_MEMORY_INDEX_NODES", 0)  # osmium's indexes in files
    ranking = rank_windows(packed, size_m=200, top=4)
    assert ranking.format == "xml.bz2"
    assert ranking.windows == expected.windows
    assert (ranking.buildings, ranking.pois, ranking.street_m) == (
        expected.buildings, expected.pois, expected.street_m,
    )  # fmt: skip


def test_data_smaller_than_a_window_is_one_window_its_extent():
    ranking = rank_windows(KIRCHBERG, size_m=500, top=10)
    (window,) = ranking.windows
    assert window.size_m[0] >= ranking.extent_m[0] and window.size_m[1] >= ranking.extent_m[1]
    assert max(window.size_m) < 500
    assert (window.buildings, window.pois, window.street_m) == (
        ranking.buildings,
        ranking.pois,
        ranking.street_m,
    )
    assert window.buildings >= 30
    # the window the recipe would name holds the data
    city = read_osm(KIRCHBERG, center=window.center, size_m=window.size_m)
    assert len(city.buildings) >= window.buildings


def test_progress_is_told_of_the_objects_read(monkeypatch):
    monkeypatch.setattr(windows_module, "_PROGRESS_EVERY", 1000)
    calls: list[tuple[str, int]] = []
    rank_windows(BERLIN, size_m=500, top=1, progress=lambda phase, done: calls.append((phase, done)))
    *steps, (phase, total) = calls
    assert steps == [("read", 1000 * n) for n in range(1, len(steps) + 1)]
    assert phase == "read" and len(steps) == total // 1000 > 10  # ways, relations and tagged nodes


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"size_m": 10}, "from 50 to 50000 m"),
        ({"size_m": math.nan}, "from 50"),
        ({"top": 0}, "from 1 to 100"),
    ],
)
def test_the_library_refuses_options_out_of_range(options: dict, message: str):
    with pytest.raises(CityMapError, match=message):
        rank_windows(NYC, **options)


# ---------------------------------------------------------------------------------------- command


def _run(args: list[str], capsys) -> tuple[int, str, str]:
    code = cli.main(args)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def outside(tmp_path: Path, monkeypatch) -> Path:
    """A current folder in no workspace."""
    for name in ("NAVVERSE_ROOT", "NAVVERSE_ALLOW_READ"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _recipe(out: str) -> str:
    """The recipe the command printed: from its description to its window's size."""
    start = out.index("description: >")
    return out[start : out.index("\n", out.index("    size_m:", start)) + 1]


def test_the_command_prints_the_table_and_without_a_workspace_the_init_that_builds_the_best(
    outside: Path, capsys
):
    code, out, err = _run(["city", "windows", str(MUNICH), "--top", "3"], capsys)
    assert code == 0, err
    rows = re.findall(r"^\|\s+(\d+) \| ([-\d.]+), ([-\d.]+) \|", out, flags=re.MULTILINE)
    assert [r[0] for r in rows] == ["1", "2", "3"]
    best = rank_windows(MUNICH, size_m=500, top=1).windows[0]
    assert (float(rows[0][1]), float(rows[0][2])) == best.center
    assert f"    center: [{best.center[0]:.6f}, {best.center[1]:.6f}]\n    size_m: [500, 500]\n" in out
    assert f"    source: {MUNICH.resolve()}\n" in out
    commands = [line.strip() for line in out.splitlines() if line.startswith("  navverse ")]
    assert commands[-1] == "navverse build munich-altstadt-500m"
    init = shlex.split(commands[0])
    assert init[:3] == ["navverse", "init", "munich-altstadt-500m"]
    code, _, err = _run(init[1:], capsys)  # runs as printed
    assert code == 0, err
    written = (
        outside / "munich-altstadt-500m" / "recipes" / "scenes" / "munich-altstadt-500m.yaml"
    ).read_text()
    assert f"center: [{best.center[0]}, {best.center[1]}]" in written and "size_m: [500, 500]" in written


def test_the_same_file_gives_the_same_output(outside: Path, capsys):
    first = _run(["city", "windows", str(NORTHGATE), "--size", "250"], capsys)
    assert first[0] == 0 and _run(["city", "windows", str(NORTHGATE), "--size", "250"], capsys) == first


@pytest.mark.slow(seconds=15)
def test_in_a_workspace_the_printed_recipe_validates_and_names_the_build(tmp_path: Path, monkeypatch, capsys):
    for name in ("NAVVERSE_ROOT", "NAVVERSE_ALLOW_READ"):
        monkeypatch.delenv(name, raising=False)
    root = tmp_path / "ws"
    write_workspace(root)
    (root / "data" / "raw" / "osm").mkdir()
    copy = root / "data" / "raw" / "osm" / NYC.name
    copy.write_bytes(NYC.read_bytes())
    monkeypatch.chdir(root)
    inside = (copy.relative_to(root), f"../../data/raw/osm/{NYC.name}", [])
    outside = (NYC, str(NYC.resolve()), ["--allow-read", str(NYC.resolve().parent)])  # needs --allow-read
    for given, source, allow in (inside, outside):
        code, out, err = _run(["city", "windows", str(given), "--top", "2"], capsys)
        assert code == 0, err
        assert "save it as recipes/scenes/nyc-lower-east-side-500m.yaml" in out
        recipe = _recipe(out)
        assert f"    source: {source}\n" in recipe and "extends: outdoor-city\n" in recipe
        build = out.strip().splitlines()[-1].strip()
        assert shlex.split(build) == ["navverse", "build", "nyc-lower-east-side-500m", *allow]
        (root / "recipes" / "scenes" / "nyc-lower-east-side-500m.yaml").write_text(recipe)
        code, out, err = _run(
            ["validate", "recipe", "recipes/scenes/nyc-lower-east-side-500m.yaml", *allow], capsys
        )
        assert code == 0 and "valid: 1 recipe file(s), 1 targets" in out, err


def _png_size(path: Path) -> tuple[int, int]:
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n", path
    return struct.unpack(">II", head[16:24])


def test_thumbnails_are_pngs_of_each_window_and_a_mosaic(outside: Path, capsys):
    code, out, err = _run(["city", "windows", str(NYC), "--top", "2", "--thumbnails", "pictures"], capsys)
    assert code == 0, err
    folder = outside / "pictures"
    assert sorted(p.name for p in folder.iterdir()) == ["1.png", "2.png", "windows.png"]
    assert _png_size(folder / "1.png") == (600, 600) and _png_size(folder / "2.png") == (600, 600)
    assert _png_size(folder / "windows.png") == (600, 300)
    assert (folder / "1.png").read_bytes() != (folder / "2.png").read_bytes()
    assert "thumbnails: 3 pictures in pictures" in out


@pytest.mark.parametrize(
    ("make", "args", "message"),
    [
        (None, ["missing.osm"], "missing.osm does not exist: give the path of an OpenStreetMap file"),
        ("text", ["notes.osm"], "notes.osm is not an OSM file"),
        ("bench", ["bench.osm"], "holds no buildings and no streets"),
        (None, [str(NYC), "--size", "20"], "--size 20: give the windows' side in meters, from 50 to 50000"),
        (None, [str(NYC), "--size", "60000"], "from 50 to 50000"),
        (None, [str(NYC), "--top", "0"], "--top 0: give how many windows to list, from 1 to 100"),
        ("text", [str(NYC), "--thumbnails", "notes.osm"], "that is a file; give a folder"),
    ],
)
def test_bad_input_is_one_line_exit_1_and_no_traceback(outside: Path, capsys, make, args, message):
    if make == "text":
        (outside / "notes.osm").write_text("just some notes\n")
    elif make == "bench":
        (outside / "bench.osm").write_text(
            '<?xml version="1.0"?>\n<osm version="0.6">\n<node id="1" version="1" lat="48.1" lon="11.5">'
            '<tag k="amenity" v="bench"/></node>\n</osm>\n'
        )
    code, out, err = _run(["city", "windows", *args], capsys)
    assert code == 1 and out == ""
    assert err.startswith("error: ") and message in err and err.count("\n") == 1, err
    assert "Traceback" not in err
