"""Scene composition: derived bounds and statistics, rigid transforms, merges, cutting volumes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from navverse.errors import SceneError
from navverse.indoor import generate_building
from navverse.scene.bev import render_bev
from navverse.scene.compose import (
    ObjectPart,
    assemble_scene,
    merge_scenes,
    remove_inside,
    scene_bounds,
    transform_scene,
)
from navverse.scene.directory import read_scene, write_scene_dir
from navverse.scene.geometry import MeshData, Scene, Surface
from navverse.scene.terrain import terrain_classes


def test_bounds_and_statistics_are_derived_from_the_parts(tiny_scene: Scene) -> None:
    ann = tiny_scene.annotations
    assert ann.bounds.min == (-2.0, -4.0, -0.1) and ann.bounds.max == (12.0, 8.0, 2.5)
    faces = sum(s.mesh.num_faces for s in tiny_scene.surfaces) + sum(
        o.mesh.num_faces for o in tiny_scene.objects
    )
    assert ann.statistics.faces == faces == 66
    assert ann.statistics.objects_per_category == {"chair": 2, "table": 1}
    assert ann.statistics.buildings == 1
    assert [o.prim_path for o in ann.objects] == [
        "/World/Objects/chair_0001",
        "/World/Objects/chair_0002",
        "/World/Objects/table_0003",
    ]
    assert ann.objects[0].size == (0.5, 0.5, 0.9)  # the extent of the local mesh


def test_assembling_nothing_or_an_unlisted_class_is_an_error() -> None:
    floor = Surface("floor", "floor", MeshData.box((2.0, 2.0, 0.1)))
    with pytest.raises(SceneError, match="needs some geometry"):
        assemble_scene(scene_id="empty", scene_type="indoor", surfaces=[])
    with pytest.raises(SceneError, match="terrain classes the scene does not list: floor"):
        assemble_scene(
            scene_id="x", scene_type="indoor", surfaces=[floor], terrain_classes=terrain_classes(["wall"])
        )


def test_transform_moves_geometry_and_every_annotation_together(tiny_scene: Scene) -> None:
    yaw, offset = math.radians(90.0), np.array([100.0, -20.0, 1.5])
    moved = transform_scene(tiny_scene, translation=offset, yaw=yaw)
    rotation = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])

    def expect(point):
        return rotation @ np.asarray(point, dtype=float) + offset

    for before, after in zip(tiny_scene.surfaces, moved.surfaces, strict=True):
        np.testing.assert_allclose(after.mesh.vertices, before.mesh.vertices @ rotation.T + offset, atol=1e-9)
    for before, after in zip(tiny_scene.objects, moved.objects, strict=True):
        np.testing.assert_allclose(
            after.world_mesh().vertices, before.world_mesh().vertices @ rotation.T + offset, atol=1e-9
        )
    building, original = moved.annotations.buildings[0], tiny_scene.annotations.buildings[0]
    np.testing.assert_allclose(
        building.footprint, [expect((*p, 0))[:2] for p in original.footprint], atol=1e-9
    )
    assert building.base_height == pytest.approx(1.5)
    south = building.facades[0]
    assert south.normal == pytest.approx((1.0, 0.0))  # -y turned by 90 degrees
    exit_ = building.exits[0]
    np.testing.assert_allclose(exit_.center, expect(original.exits[0].center), atol=1e-9)
    assert exit_.facing == pytest.approx(0.0)
    storefront = moved.annotations.storefronts[0]
    np.testing.assert_allclose(storefront.entrance, expect(tiny_scene.annotations.storefronts[0].entrance))
    np.testing.assert_allclose(moved.annotations.indoor_anchor, expect((5.0, 4.0, 0.0)))
    assert moved.annotations.bounds == scene_bounds(moved.surfaces, moved.objects)
    back = transform_scene(transform_scene(moved, translation=-offset), yaw=-yaw)
    for a, b in zip(back.annotations.objects, tiny_scene.annotations.objects, strict=True):
        np.testing.assert_allclose(a.center, b.center, atol=1e-9)
        assert math.remainder(a.yaw - b.yaw, math.tau) == pytest.approx(0.0, abs=1e-12)


@pytest.fixture(scope="module")
def two_buildings() -> tuple[Scene, Scene]:
    first = generate_building("cafe", np.random.default_rng(3), scene_id="cafe-a")
    second = generate_building("apartment", np.random.default_rng(4), scene_id="apartment-b")
    return first, transform_scene(second, translation=(40.0, 5.0, 0.0), yaw=math.radians(30.0))


def test_merged_buildings_keep_their_parts_with_fresh_ids(two_buildings) -> None:
    first, second = two_buildings
    merged = merge_scenes([first, second], scene_id="two-buildings", scene_type="indoor")
    ann = merged.annotations
    assert [b.id for b in ann.buildings] == [1, 2]
    for kind in ("rooms", "doors", "exits"):
        ids = [x.id for x in getattr(ann, kind)]
        expected = len(getattr(first.annotations, kind)) + len(getattr(second.annotations, kind))
        assert ids == list(range(1, expected + 1)), kind
    facade_ids = [f.id for b in ann.buildings for f in b.facades]
    assert facade_ids == list(range(1, len(facade_ids) + 1))
    # the second building's doors name its own (renumbered) rooms
    shift = len(first.annotations.rooms)
    assert [d.rooms for d in ann.buildings[1].doors] == [
        tuple(r + shift for r in d.rooms) for d in second.annotations.doors
    ]
    assert all(e.facade in {f.id for f in ann.buildings[1].facades} for e in ann.buildings[1].exits)
    # objects renumbered, prim paths unique, surfaces renamed where they clashed
    assert [o.id for o in ann.objects] == list(range(1, len(first.objects) + len(second.objects) + 1))
    assert len({o.prim_path for o in ann.objects}) == len(ann.objects)
    names = [s.name for s in merged.surfaces]
    assert len(set(names)) == len(names) and "floor" in names and "floor_2" in names
    assert list(ann.terrain_classes) == list(first.annotations.terrain_classes)
    assert ann.indoor_polygons == [b.footprint for b in ann.buildings]
    assert ann.statistics.buildings == 2
    assert ann.bounds.max[0] > first.annotations.bounds.max[0] + 20


def test_a_merged_scene_round_trips_through_json_and_usd(two_buildings, tmp_path: Path) -> None:
    merged = merge_scenes(list(two_buildings), scene_id="two-buildings", scene_type="indoor")
    write_scene_dir(merged, tmp_path, bev=False)
    again = read_scene(tmp_path)
    assert again.annotations == merged.annotations
    from navverse.scene.usd import read_usd

    usd = read_usd(tmp_path / "scene.usdc")
    assert usd.buildings is not None and list(usd.buildings) == merged.annotations.buildings
    assert [len(b.rooms) for b in usd.buildings] == [len(b.rooms) for b in merged.annotations.buildings]
    info = render_bev(again, tmp_path / "bev.png")
    (lo_x, lo_y, _), (hi_x, hi_y, _) = merged.annotations.bounds.min, merged.annotations.bounds.max
    rows, cols = info.raster_shape
    assert cols * info.meters_per_pixel >= hi_x - lo_x and rows * info.meters_per_pixel >= hi_y - lo_y


def test_usd_and_json_that_disagree_on_buildings_are_refused(two_buildings, tmp_path: Path) -> None:
    first, _ = two_buildings
    write_scene_dir(first, tmp_path, bev=False)
    moved = first.annotations.buildings[0].model_copy(update={"height": 99.0})
    from navverse.scene.annotations import save_annotations

    save_annotations(first.annotations.model_copy(update={"buildings": [moved]}), tmp_path / "scene.json")
    with pytest.raises(SceneError, match=r"buildings .* differ"):
        read_scene(tmp_path)


def test_merging_scenes_with_conflicting_terrain_classes_is_an_error(tiny_scene: Scene) -> None:
    other = terrain_classes(["floor", "wall", "ceiling", "road"])  # road with its default friction
    clash = assemble_scene(
        scene_id="other", scene_type="outdoor", surfaces=tiny_scene.surfaces, terrain_classes=other
    )
    with pytest.raises(SceneError, match="terrain class 'road' differs"):
        merge_scenes([tiny_scene, clash], scene_id="m", scene_type="i2o")


def test_remove_inside_cuts_a_door_out_of_a_wall() -> None:
    wall = MeshData.box((4.0, 0.2, 3.0), center=(0.0, 0.0, 1.5))
    red = np.tile(np.array([[200, 30, 30]], dtype=np.uint8), (wall.num_faces, 1))
    floor = MeshData(
        np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0], [0, 0.5, 0]], dtype=float),
        np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]),
    )
    scene = assemble_scene(
        scene_id="wall",
        scene_type="outdoor",
        surfaces=[
            Surface("wall", "wall", MeshData(wall.vertices, wall.faces, red)),
            Surface("ground", "ground", floor),
        ],
        objects=[
            ObjectPart("bench", MeshData.box((0.6, 0.6, 0.6)), (0.2, 0.0, 0.3)),  # in the doorway
            ObjectPart("bench", MeshData.box((0.6, 0.6, 0.6)), (2.5, 2.5, 0.3)),  # well away
        ],
    )
    door = MeshData.box((1.0, 1.0, 2.0), center=(0.0, 0.0, 1.0))
    cut = remove_inside(scene, door)
    carved = next(s.mesh for s in cut.surfaces if s.name == "wall")
    import trimesh

    solid = trimesh.Trimesh(carved.vertices, carved.faces)
    assert solid.is_watertight
    assert solid.volume == pytest.approx(4.0 * 0.2 * 3.0 - 1.0 * 0.2 * 2.0, rel=1e-6)
    assert (carved.face_colors == (200, 30, 30)).all(axis=1).any()
    ground = next(s.mesh for s in cut.surfaces if s.name == "ground")
    assert ground.num_faces == 4  # no ground triangle lies wholly inside the door's volume
    assert [o.center for o in cut.annotations.objects] == [(2.5, 2.5, 0.3)]
    assert cut.annotations.objects[0].id == 1
    with pytest.raises(SceneError, match="closed"):
        remove_inside(scene, MeshData(door.vertices, door.faces[:-2]))
