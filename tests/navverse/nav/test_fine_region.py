"""Mixed resolution: the tiles meeting ``fine_region`` are built with cells ``fine_factor`` times finer."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from navverse import nav
from navverse.nav import NavMeshError, NavMeshSettings, PathFinder
from navverse.nav.fileformat import read_navmesh, write_navmesh
from navverse.nav.settings import NavMeshOverrides
from tests.navverse.nav import scenes

# The extension's tile payload (navmesh.cpp, NavMesh::toBytes): magic, version, Detour version,
# reference size, dtNavMeshParams (orig, tile width and height, max tiles and polygons), tile count;
# then per tile its reference, size and Detour data, which starts with a dtMeshHeader.
PAYLOAD_HEAD = struct.Struct("<4sIii3fffiii")
TILE_HEAD = struct.Struct("<Qi")
MESH_HEADER = struct.Struct("<15i3f3f3ff")  # ints magic .. offMeshBase, walkable*, bmin, bmax, bvQuantFactor

TILE = 32  # cells: 3.2 m tiles at the outdoor cell size
# A 40 m x 6 m floor: 13 x 2 tiles; the region spans the middle ones (x 14..26) in both rows.
FLOOR = (0.0, 0.0, 40.0, 6.0)
MIDDLE = (14.0, 2.0, 26.0, 4.0)


def tile_cell_sizes(finder: PathFinder) -> dict[tuple[int, int], tuple[float, np.ndarray]]:
    """Per tile (x, y): its cell size (Detour header) and its core, world [xmin, ymin, xmax, ymax]."""
    _, payload = read_navmesh(finder.to_bytes())
    _, _, _, _, ox, _, oz, width, height, _, _, count = PAYLOAD_HEAD.unpack_from(payload)
    offset = PAYLOAD_HEAD.size
    tiles = {}
    for _ in range(count):
        _, size = TILE_HEAD.unpack_from(payload, offset)
        header = MESH_HEADER.unpack_from(payload, offset + TILE_HEAD.size)
        offset += TILE_HEAD.size + size
        tx, ty = header[2], header[3]
        # Recast (x, z) is world (x, -y).
        core = np.array(
            [ox + tx * width, -(oz + (ty + 1) * height), ox + (tx + 1) * width, -(oz + ty * height)]
        )
        tiles[(tx, ty)] = (round(1.0 / header[-1], 6), core)
    return tiles


def payload(finder: PathFinder) -> bytes:
    """The Detour tiles of a navmesh file, without its metadata."""
    return read_navmesh(finder.to_bytes())[1]


def build(builder: scenes.MeshBuilder, settings: NavMeshSettings, *, jobs: int = 2) -> PathFinder:
    vertices, faces, areas = builder.arrays()
    return nav.build(vertices, faces, settings, area_types=areas, jobs=jobs)


def long_floor() -> scenes.MeshBuilder:
    x0, y0, x1, y1 = FLOOR
    return scenes.MeshBuilder().floor(x0, y0, x1, y1)


# A wall band y in [5, 7] across a 20 m x 12 m floor, open only at a 0.75 m gap (x in [10.06, 10.81])
# joining the south half to the north half. With agent_radius 0.3 the gap leaves 0.15 m of free
# width. Cell boundaries lie at x = -0.05 + k * cell (the grid starts half a cell before the
# mesh), so each wall face is 1 cm past one: 10 cm cells lose the cells holding the faces (6 clear
# cells remain, eroded by 3 on each side: closed); 5 cm cells keep 14 clear cells, eroded by 6 on
# each side: a 0.1 m strip stays walkable.
GAP = (10.06, 10.81)
SOUTH, NORTH = [10.45, 2.0, 0.0], [10.45, 10.0, 0.0]
GAP_REGION = (8.0, 3.0, 13.0, 9.0)
NARROW = {"agent_radius": 0.3, "tile_size": TILE}


def gap_hall() -> scenes.MeshBuilder:
    x0, x1 = GAP
    b = scenes.MeshBuilder().floor(0, 0, 20, 12)
    return b.box((0, 5, 0), (x0, 7, 2.5), scenes.WALL).box((x1, 5, 0), (20, 7, 2.5), scenes.WALL)


@pytest.fixture(scope="module")
def mixed_floor() -> PathFinder:
    return build(long_floor(), nav.I2O.with_overrides({"tile_size": TILE, "fine_region": MIDDLE}))


def test_tiles_meeting_the_region_are_fine(mixed_floor: PathFinder):
    tiles = tile_cell_sizes(mixed_floor)
    assert len(tiles) == 26  # 13 x 2
    x0, y0, x1, y1 = MIDDLE
    fine = set()
    for key, (cell, (tx0, ty0, tx1, ty1)) in tiles.items():
        meets = tx0 < x1 and x0 < tx1 and ty0 < y1 and y0 < ty1
        assert cell == (0.05 if meets else 0.1), key
        fine |= {key} if meets else set()
    assert fine == {(x, y) for x in range(4, 9) for y in range(2)}  # x in [12.75, 28.75]: tiles 4..8


@pytest.mark.parametrize(
    ("start", "end"),
    [
        ((1.5, 3.0), (38.5, 3.0)),
        ((1.5, 1.2), (38.5, 4.8)),
        ((1.0, 5.2), (39.0, 0.8)),
        ((13.0, 1.0), (27.0, 5.0)),
    ],
)
def test_paths_cross_between_coarse_and_fine_tiles(mixed_floor: PathFinder, start, end):
    # Each path runs from a coarse tile through the fine ones into coarse tiles again: on an open
    # floor it is the straight line, so tiles of both resolutions are linked along their borders.
    assert mixed_floor.num_islands == 1
    path = mixed_floor.find_path([*start, 0.0], [*end, 0.0])
    assert path.found
    assert path.geodesic_distance == pytest.approx(np.hypot(end[0] - start[0], end[1] - start[1]), abs=0.02)


def test_narrow_corridor_is_open_only_in_fine_tiles():
    coarse = build(gap_hall(), nav.OUTDOOR.with_overrides(NARROW))
    assert coarse.geodesic_distance(SOUTH, NORTH) == np.inf
    assert coarse.num_islands == 2

    mixed = build(gap_hall(), nav.I2O.with_overrides({**NARROW, "fine_region": GAP_REGION}))
    assert mixed.num_islands == 1
    assert mixed.geodesic_distance(SOUTH, NORTH) == pytest.approx(8.0, abs=0.05)
    # The same as 5 cm cells everywhere.
    indoor = build(gap_hall(), nav.INDOOR.with_overrides({**NARROW, "tile_size": 2 * TILE}))
    assert indoor.geodesic_distance(SOUTH, NORTH) == pytest.approx(8.0, abs=0.05)

    # A region elsewhere leaves the corridor at 10 cm: closed.
    elsewhere = build(gap_hall(), nav.I2O.with_overrides({**NARROW, "fine_region": (0.0, 0.0, 3.0, 3.0)}))
    assert elsewhere.geodesic_distance(SOUTH, NORTH) == np.inf


@pytest.mark.parametrize(
    "changes",
    [
        {"fine_factor": 2, "fine_region": (100.0, 100.0, 110.0, 110.0)},  # meets no tile
        {"fine_factor": 2, "fine_region": None},  # the I2O preset before a region is set
        {"fine_factor": 1, "fine_region": MIDDLE},
    ],
    ids=["region-outside", "no-region", "factor-1"],
)
def test_without_fine_tiles_the_tiles_are_the_plain_build(changes: dict):
    plain = build(long_floor(), nav.OUTDOOR.with_overrides({"tile_size": TILE}))
    same = build(long_floor(), nav.OUTDOOR.with_overrides({"tile_size": TILE, **changes}))
    assert payload(same) == payload(plain)
    assert {cell for cell, _ in tile_cell_sizes(same).values()} == {0.1}


def test_mixed_builds_are_deterministic():
    settings = nav.I2O.with_overrides({**NARROW, "fine_region": GAP_REGION})
    one = build(gap_hall(), settings, jobs=1)
    two = build(gap_hall(), settings, jobs=2)
    assert one.to_bytes() == two.to_bytes() == build(gap_hall(), settings, jobs=2).to_bytes()


def test_files_round_trip_the_mixed_settings(mixed_floor: PathFinder, tmp_path: Path):
    file = tmp_path / "mixed.navmesh"
    mixed_floor.save(file)
    loaded = PathFinder.load(file)
    assert loaded.settings == mixed_floor.settings
    assert loaded.settings.fine_region == MIDDLE and loaded.settings.fine_factor == 2
    assert loaded.to_bytes() == file.read_bytes()
    start, end = [1.5, 1.2, 0.0], [38.5, 4.8, 0.0]
    assert loaded.geodesic_distance(start, end) == mixed_floor.geodesic_distance(start, end)


def test_single_resolution_files_have_no_mixed_resolution_keys(tmp_path: Path):
    # Files of single-resolution navmeshes are the ones written before the mixed-resolution fields
    # existed: their settings have no such keys, and loading fills in the defaults.
    finder = build(long_floor(), nav.OUTDOOR.with_overrides({"tile_size": TILE}))
    meta, tiles = read_navmesh(finder.to_bytes())
    assert "fine_region" not in meta["settings"] and "fine_factor" not in meta["settings"]
    loaded = PathFinder.from_bytes(finder.to_bytes())
    assert loaded.settings == finder.settings
    assert loaded.settings.fine_region is None and loaded.settings.fine_factor == 1
    # The I2O preset without a region keeps its factor.
    i2o = build(long_floor(), nav.I2O.with_overrides({"tile_size": TILE}))
    assert PathFinder.from_bytes(i2o.to_bytes()).settings == i2o.settings
    # An old file, written by write_navmesh with the settings of the time.
    old = write_navmesh(tiles, **{key: value for key, value in meta.items() if key != "format_version"})
    assert PathFinder.from_bytes(old).settings == finder.settings


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"fine_region": (5.0, 0.0, 1.0, 4.0)}, "xmin < xmax and ymin < ymax"),
        ({"fine_region": (0.0, 4.0, 5.0, 4.0)}, "xmin < xmax and ymin < ymax"),
        ({"fine_region": (0.0, 0.0, 5.0, float("nan"))}, "fine_region.3: Input should be a finite number"),
        ({"fine_region": (0.0, 0.0, 5.0)}, "fine_region.3: Field required"),
        ({"fine_region": (0.0, 0.0, 5.0, 5.0), "tile_size": 0}, "fine_region needs a tiled build"),
        ({"fine_factor": 5}, "fine_factor: Input should be less than or equal to 4"),
        ({"fine_factor": 0}, "fine_factor: Input should be greater than or equal to 1"),
        ({"fine_factor": 1.5}, "fine_factor: Input should be a valid integer"),
        (
            {"fine_region": (0.0, 0.0, 5.0, 5.0), "fine_factor": 4, "tile_size": 2048},
            "tile_size \\* fine_factor = 8192 cells per side, more than 4096",
        ),
        (
            {"fine_region": (0.0, 0.0, 5.0, 5.0), "fine_factor": 4, "agent_radius": 7.0},
            r"more than 250 cells of cell_size 0.025 m \(cell_size / fine_factor\).*decrease fine_factor",
        ),
    ],
)
def test_invalid_mixed_resolution_settings(changes: dict, match: str):
    with pytest.raises(NavMeshError, match=f"invalid navmesh settings: .*{match}"):
        nav.I2O.with_overrides(changes)


def test_invalid_settings_stop_the_build():
    vertices, faces, areas = long_floor().arrays()
    unchecked = nav.I2O.model_copy(
        update={"tile_size": 0, "fine_region": MIDDLE}
    )  # model_copy skips validation
    with pytest.raises(NavMeshError, match="fine_region needs a tiled build"):
        nav.build(vertices, faces, unchecked, area_types=areas)


def test_overrides_carry_the_mixed_resolution_fields():
    overrides = NavMeshOverrides.model_validate({"fine_region": [1, 2, 3, 4], "fine_factor": 3})
    settings = nav.OUTDOOR.with_overrides(overrides)
    assert settings.fine_region == (1.0, 2.0, 3.0, 4.0) and settings.fine_factor == 3
    assert nav.I2O.with_overrides(NavMeshOverrides()) == nav.I2O  # unset fields keep the preset's
