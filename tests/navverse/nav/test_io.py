"""Saved navmeshes load back with identical query results; foreign or stale files are refused."""

from __future__ import annotations

import json
import re
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

from navverse import nav
from navverse.nav import NavMeshError, PathFinder
from navverse.nav.fileformat import FORMAT_VERSION, MAGIC
from tests.navverse.nav import scenes
from tests.navverse.nav.conftest import build_scene

QUERIES = [
    ([1.0, 1.0, 0.0], [29.0, 19.0, 0.0]),
    ([3.0, 5.0, 0.0], [22.0, 17.0, 0.0]),
    ([28.0, 8.0, 0.0], [2.0, 9.0, 0.0]),
]
HEADER = struct.Struct("<8sIIQI")


@pytest.fixture(scope="module")
def hall() -> PathFinder:
    finder = build_scene(scenes.hall_with_pillars(), nav.OUTDOOR, tile_size=64)
    finder.set_area_costs({scenes.FLOOR: 1.5})
    finder.set_excluded_areas({40})
    return finder


def assert_same_answers(a: PathFinder, b: PathFinder) -> None:
    for start, end in QUERIES:
        pa, pb = a.find_path(start, end), b.find_path(start, end)
        assert pa.geodesic_distance == pb.geodesic_distance
        np.testing.assert_array_equal(pa.points, pb.points)
    probes = np.array([[5.0, 5.0, 0.3], [15.0, 1.0, 0.0], [100.0, 0.0, 0.0]])
    np.testing.assert_array_equal(a.snap_point(probes), b.snap_point(probes))
    np.testing.assert_array_equal(a.island_of(probes), b.island_of(probes))
    np.testing.assert_array_equal(
        a.distance_to_closest_obstacle(probes), b.distance_to_closest_obstacle(probes)
    )
    for seed in (1, 2, 3):
        np.testing.assert_array_equal(a.get_random_navigable_point(seed), b.get_random_navigable_point(seed))
        np.testing.assert_array_equal(
            a.get_random_navigable_point_near([5.0, 5.0, 0.0], 2.0, seed),
            b.get_random_navigable_point_near([5.0, 5.0, 0.0], 2.0, seed),
        )
    assert a.navigable_area == b.navigable_area
    assert a.num_islands == b.num_islands and a.num_polygons == b.num_polygons
    np.testing.assert_array_equal(a.bounds, b.bounds)
    for pa, pb in zip(a.polygons(), b.polygons(), strict=True):
        np.testing.assert_array_equal(pa, pb)


def test_save_load_gives_identical_answers(hall: PathFinder, tmp_path: Path):
    path = tmp_path / "navmesh.bin"
    hall.save(path)
    loaded = nav.load(path)
    assert loaded.settings == hall.settings
    assert loaded.area_costs == {scenes.FLOOR: 1.5}
    assert loaded.excluded_areas == {40}
    assert_same_answers(hall, loaded)
    assert loaded.to_bytes() == hall.to_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["navmesh.bin"]  # no temp file left


def test_file_header(hall: PathFinder):
    data = hall.to_bytes()
    magic, version, meta_len, tiles_len, crc = HEADER.unpack_from(data)
    assert magic == MAGIC and version == FORMAT_VERSION
    assert len(data) == HEADER.size + meta_len + tiles_len
    meta = json.loads(data[HEADER.size : HEADER.size + meta_len])
    # Single resolution: the settings without the mixed-resolution fields (as before they existed).
    assert meta["settings"] == hall.settings.model_dump(mode="json", exclude={"fine_region", "fine_factor"})
    assert meta["area_types"] == [scenes.FLOOR]
    assert crc == zlib.crc32(data[HEADER.size :])


def repack(
    data: bytes, *, version: int | None = None, meta: dict | None = None, tiles: bytes | None = None
) -> bytes:
    _, old_version, meta_len, _, _ = HEADER.unpack_from(data)
    old_meta = data[HEADER.size : HEADER.size + meta_len]
    meta_bytes = json.dumps(meta).encode() if meta is not None else old_meta
    tile_bytes = tiles if tiles is not None else data[HEADER.size + meta_len :]
    body = meta_bytes + tile_bytes
    head = HEADER.pack(
        MAGIC, old_version if version is None else version, len(meta_bytes), len(tile_bytes), zlib.crc32(body)
    )
    return head + body


def test_other_format_version_is_refused(hall: PathFinder, tmp_path: Path):
    path = tmp_path / "old.bin"
    path.write_bytes(repack(hall.to_bytes(), version=FORMAT_VERSION + 1))
    message = (
        f"navmesh file format v{FORMAT_VERSION + 1}, this toolkit reads v{FORMAT_VERSION}: "
        "rebuild it with `navverse build --verify <scene_id>`"
    )
    with pytest.raises(NavMeshError, match=re.escape(message)):
        nav.load(path)


@pytest.mark.parametrize(
    ("content", "match"),
    [
        (b"", "not a navverse navmesh file"),
        (b"glTF\x02\x00\x00\x00 some other file", "not a navverse navmesh file"),
        (MAGIC + b"\x01", "truncated"),
    ],
)
def test_foreign_files_are_refused(tmp_path: Path, content: bytes, match: str):
    path = tmp_path / "x.bin"
    path.write_bytes(content)
    with pytest.raises(NavMeshError, match=match):
        nav.load(path)


def test_missing_file(tmp_path: Path):
    with pytest.raises(NavMeshError, match="cannot read navmesh file"):
        nav.load(tmp_path / "nope.bin")


def test_damaged_files_are_refused(hall: PathFinder):
    data = hall.to_bytes()
    with pytest.raises(NavMeshError, match="truncated or damaged"):
        PathFinder.from_bytes(data[:-7])
    flipped = bytearray(data)
    flipped[-100] ^= 0xFF
    with pytest.raises(NavMeshError, match="truncated or damaged"):
        PathFinder.from_bytes(bytes(flipped))


def test_inconsistent_tiles_with_a_valid_checksum_are_refused(hall: PathFinder):
    # Corrupt a tile header's polygon count, then fix the checksum: the extension must refuse the
    # tile rather than let Detour read past its data.
    data = hall.to_bytes()
    _, _, meta_len, _, _ = HEADER.unpack_from(data)
    tiles = bytearray(data[HEADER.size + meta_len :])
    first_tile = 4 + 4 + 4 + 4 + 5 * 4 + 2 * 4 + 4 + 8 + 4  # blob header, params, count, ref, size
    poly_count = first_tile + 6 * 4  # magic, version, x, y, layer, userId
    tiles[poly_count : poly_count + 4] = struct.pack("<i", 1_000_000)
    with pytest.raises(NavMeshError, match="corrupt"):
        PathFinder.from_bytes(repack(data, tiles=bytes(tiles)))


def test_unreadable_settings_are_refused(hall: PathFinder):
    data = hall.to_bytes()
    _, _, meta_len, _, _ = HEADER.unpack_from(data)
    meta = json.loads(data[HEADER.size : HEADER.size + meta_len])
    meta["settings"]["voxel_size"] = 0.1
    with pytest.raises(NavMeshError, match="settings do not validate"):
        PathFinder.from_bytes(repack(data, meta=meta))
