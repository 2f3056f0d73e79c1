"""Scene fields: terrain, obstacles (the body band above the walkable ground), indoor raster, cache."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from navverse.scene.compose import ObjectPart, object_parts, replace_parts
from navverse.scene.directory import write_scene_dir
from navverse.scene.fields import (
    BODY_HEIGHT,
    NO_SURFACE,
    OBSTACLE_MIN_HEIGHT,
    SceneFields,
    fields_cache_path,
    load_scene_fields,
    scene_fields,
)
from navverse.scene.geometry import MeshData, Scene, Surface
from tests.scenes import box_part, quad, scene_of

from .conftest import FLOOR_POINT, ROAD_POINT, WALL_POINT


@pytest.fixture(scope="module")
def fields(tiny_scene: Scene) -> SceneFields:
    return scene_fields(tiny_scene)


def test_indoor_raster_of_the_tiny_scene(fields: SceneFields) -> None:
    # Bounds x -2..12, y -4..8 at 0.1 m (i2o): 120 x 140 cells; indoor is x 0..10, y 0..8.
    assert fields.cell == pytest.approx(0.1) and fields.indoor.shape == (120, 140)
    assert fields.indoor.sum() == 100 * 80 and fields.has_indoor
    assert fields.indoor[40:120, 20:120].all()
    points = [FLOOR_POINT, WALL_POINT, ROAD_POINT, (-0.05, 4.0), (10.05, 4.0), (5.0, 7.95), (5.0, 8.5)]
    assert fields.indoor_at(points).tolist() == [True, True, False, False, False, True, False]
    # Beyond the grid is outdoors, even next to an indoor border cell (row 119 is indoor).
    assert not fields.indoor_at([(5.0, 20.0)])[0]
    names = list(fields.class_names)
    assert fields.terrain_at([FLOOR_POINT, ROAD_POINT]).tolist() == [
        names.index("floor"),
        names.index("road"),
    ]


def test_fields_without_an_indoor_raster_have_none() -> None:
    plain = SceneFields((0.0, 0.0), 1.0, np.zeros((2, 3), np.int16), np.zeros((2, 3), bool),
                        np.ones((2, 3), np.float32), ("floor",))  # fmt: skip
    assert plain.indoor.shape == (2, 3) and not plain.has_indoor
    assert plain.indoor_at([(0.5, 0.5)]).tolist() == [False]
    with pytest.raises(ValueError, match="indoor raster"):
        SceneFields(
            plain.origin, 1.0, plain.terrain, plain.obstacle, plain.distance, ("floor",), np.ones((3, 2))
        )


def test_walls_and_objects_of_the_tiny_scene_are_obstacles(fields: SceneFields) -> None:
    names = list(fields.class_names)
    chair, table = (3.0, 5.0), (7.0, 5.0)
    assert fields.obstacle[fields.cells([WALL_POINT, chair, table])].tolist() == [True] * 3
    assert fields.terrain_at([WALL_POINT])[0] == names.index("wall")
    assert not fields.obstacle[fields.cells([FLOOR_POINT, ROAD_POINT])].any()
    # The nearest obstacle is the south wall, whose face is 1.7 m away (1.8 m between cell centres).
    assert fields.distance_at([FLOOR_POINT])[0] == pytest.approx(1.75, abs=fields.cell)


def _box(size: tuple[float, float, float], low: tuple[float, float, float]) -> MeshData:
    """A closed box of `size` whose minimum corner is `low`."""
    return MeshData.box(size, center=tuple(lo + s / 2.0 for lo, s in zip(low, size, strict=True)))


def _table(size: tuple[float, float, float], top: float = 0.04, leg: float = 0.06) -> MeshData:
    """A table centred on the origin: a top slab on four legs (an open space under the top)."""
    sx, sy, sz = size
    parts = [_box((sx, sy, top), (-sx / 2, -sy / 2, sz / 2 - top))]
    for fx in (-1, 1):
        for fy in (-1, 1):
            x = -leg / 2 + fx * (sx - leg) / 2
            y = -leg / 2 + fy * (sy - leg) / 2
            parts.append(_box((leg, leg, sz - top), (x, y, -sz / 2)))
    return MeshData.concatenate(parts)


#: The objects of the door scene (ids 1 to 5 in this order); their meshes are object-local.
DOOR_SCENE_OBJECTS = (
    ObjectPart("pendant_lamp", MeshData.box((0.5, 0.5, 0.3)), (6.0, 1.5, 2.15)),  # hangs from 2.0 to 2.3 m
    ObjectPart("table", _table((1.2, 0.8, 0.75)), (2.0, 1.5, 0.375)),
    ObjectPart("rug", MeshData.box((1.0, 1.0, 0.01)), (6.0, 4.5, 0.005)),
    ObjectPart("shelf", MeshData.box((0.8, 0.3, 0.04)), (6.5, 2.8, 1.4)),  # wall shelf at 1.38-1.42 m
    ObjectPart("wardrobe", MeshData.box((0.6, 0.6, 2.0)), (1.0, 4.5, 1.0)),  # taller than the band
)
DOORWAY = (3.5, 3.0)  # middle of the opening, under the header
WALL = ((1.5, 3.0), (6.0, 3.0), (0.5, 5.9))  # the dividing wall either side of the door; the north wall


def build_door_scene() -> Scene:
    """Two rooms on a floor slab (x 0..8, y 0..6, top at z = 0) divided at y = 3 by a 2.5 m wall with a
    door x 3..4 under a header from 2.1 m; a north wall that runs on 1 m past both ends of the floor,
    over nothing, so that the scene (its bounds: x -1..9) reaches beyond the floor; objects; a puddle
    of water on the floor."""
    wall = MeshData.concatenate(
        [
            _box((3.0, 0.2, 2.5), (0.0, 2.9, 0.0)),
            _box((4.0, 0.2, 2.5), (4.0, 2.9, 0.0)),
            _box((1.0, 0.2, 0.4), (3.0, 2.9, 2.1)),  # the header above the door
            _box((10.0, 0.2, 2.5), (-1.0, 5.8, 0.0)),
        ]
    )
    surfaces = (
        Surface("floor", "floor", _box((8.0, 6.0, 0.1), (0.0, 0.0, -0.1))),
        Surface("walls", "wall", wall),
        Surface("ceiling", "ceiling", quad(0.0, 0.0, 8.0, 6.0, 2.5)),
        Surface("puddle", "water", quad(4.5, 0.5, 5.5, 1.0, 0.0)),
    )
    return scene_of(surfaces, DOOR_SCENE_OBJECTS, scene_id="door_rooms")


@pytest.fixture(scope="module")
def door_fields() -> SceneFields:
    return scene_fields(build_door_scene())


def test_the_body_band_sets_the_obstacles(door_fields: SceneFields) -> None:
    f = door_fields
    names = list(f.class_names)
    floor, wall, water = names.index("floor"), names.index("wall"), names.index("water")
    assert f.cell == pytest.approx(0.05) and 0.0 < OBSTACLE_MIN_HEIGHT < 0.75 < BODY_HEIGHT < 2.0

    def blocked(*points: tuple[float, float]) -> list[bool]:
        return f.obstacle[f.cells(points)].tolist()

    # The walls block, their bottoms on the floor's top (the rays start inside them); the doorway is
    # free and reads the floor.
    assert blocked(*WALL) == [True] * 3 and f.terrain_at(WALL).tolist() == [wall] * 3
    assert blocked(DOORWAY, (3.1, 3.0), (3.9, 3.0)) == [False] * 3
    assert f.terrain_at([DOORWAY])[0] == floor
    door_cells = f.obstacle[f.cells([(x, 3.0) for x in np.arange(3.025, 4.0, 0.05)])]
    assert not door_cells.any() and f.obstacle[f.cells([(2.975, 3.0), (4.025, 3.0)])].all()
    # The distance in the doorway is to the jambs, 0.5 m from its middle.
    assert f.distance_at([DOORWAY])[0] == pytest.approx(0.5, abs=f.cell)
    # Above the band: the pendant lamp and the wall shelf are free; within it: the table top (the
    # space under it too: the body cannot pass) and the wardrobe; the rug is under the band.
    assert blocked((6.0, 1.5), (6.2, 1.7), (6.5, 2.8)) == [False] * 3
    assert blocked((2.0, 1.5), (1.5, 1.2), (2.55, 1.85), (1.0, 4.5), (1.25, 4.25)) == [True] * 5
    assert blocked((6.0, 4.5), (5.6, 4.1)) == [False] * 2
    assert f.terrain_at([(6.0, 1.5), (2.0, 1.5), (6.0, 4.5)]).tolist() == [floor] * 3
    # Water at ground level blocks and names its cells.
    assert blocked((5.0, 0.75)) == [True] and f.terrain_at([(5.0, 0.75)])[0] == water
    # Beyond the floor there is nothing at all: free, no surface.
    assert blocked((-0.5, 1.0), (8.5, 1.0)) == [False] * 2
    assert f.terrain_at([(-0.5, 1.0)])[0] == NO_SURFACE
    # The middle of the north room is as far from the obstacles as its walls' faces (y 3.1 and 5.8).
    assert f.distance_at([(4.5, 4.45)])[0] == pytest.approx(1.35, abs=f.cell)


def test_objects_without_walkable_ground_block() -> None:
    scene = build_door_scene()
    # A crate on the bare void beyond the floor (x < 0): no ground under it, it blocks.
    crate = box_part("crate", (-0.5, 3.0, 0.2), (0.4, 0.4, 0.4))
    f = scene_fields(replace_parts(scene, objects=[*object_parts(scene), crate]))
    assert f.obstacle[f.cells([(-0.5, 3.0)])].tolist() == [True]
    assert f.obstacle[f.cells([(-0.5, 1.0)])].tolist() == [False]


def test_the_cache_round_trips_and_rebuilds_files_of_the_old_format(
    tiny_scene: Scene, fields: SceneFields, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(tmp_path / "cache"))
    scene_dir = tmp_path / "scene"
    scene_dir.mkdir()
    write_scene_dir(tiny_scene, scene_dir, bev=False)
    first = load_scene_fields(scene_dir)
    path = fields_cache_path(scene_dir)
    assert path.is_file()
    loaded = SceneFields.load(path)
    assert loaded is not None and np.array_equal(loaded.indoor, fields.indoor)
    assert np.array_equal(first.indoor, fields.indoor) and np.array_equal(loaded.terrain, fields.terrain)
    # Files of format 1 (no indoor raster) and 2 (obstacles from the top surfaces) are not trusted: they
    # are recomputed and rewritten.
    for old in (1, 2):
        np.savez_compressed(
            path,
            format=np.int64(old),
            origin=np.asarray(fields.origin),
            cell=np.float64(fields.cell),
            terrain=fields.terrain,
            obstacle=fields.obstacle,
            distance=fields.distance,
            class_names=np.asarray(fields.class_names, dtype=str),
            indoor=fields.indoor,
        )
        assert SceneFields.load(path) is None
        again = load_scene_fields(scene_dir)
        assert again.has_indoor and SceneFields.load(path) is not None
    # A file cut short (a full disk, a copy stopped midway) is recomputed too.
    path.write_bytes(path.read_bytes()[:100])
    assert SceneFields.load(path) is None
    assert np.array_equal(load_scene_fields(scene_dir).terrain, fields.terrain)


def test_fields_cast_in_bands_of_any_size_are_the_same(tiny_scene: Scene, fields: SceneFields) -> None:
    columns = fields.terrain.shape[1]
    for rays in (1, columns - 1, 3 * columns + 5):  # a row at a time (1 and rows - 1), and bands cut mid-grid
        banded = scene_fields(tiny_scene, rays_per_band=rays)
        for name in ("terrain", "obstacle", "distance", "indoor"):
            assert np.array_equal(getattr(banded, name), getattr(fields, name)), (rays, name)
    with pytest.raises(ValueError, match="rays_per_band must be positive"):
        scene_fields(tiny_scene, rays_per_band=0)


def test_the_obstacle_distance_is_scipy_s_exact_transform_bit_for_bit() -> None:
    from navverse.scene.fields import _obstacle_distance

    rng = np.random.default_rng(3)
    for shape, density in (((37, 53), 0.02), ((64, 9), 0.3), ((5, 200), 0.001)):
        obstacle = rng.random(shape) < density
        obstacle[0, 0] = True
        expected = ndimage.distance_transform_edt(~obstacle).astype(np.float32) * np.float32(0.1)
        for rows in (1, 4, shape[0]):
            assert _obstacle_distance(obstacle, 0.1, rows).tobytes() == expected.tobytes()
