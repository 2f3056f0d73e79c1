from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from pxr import Usd, UsdGeom, UsdPhysics, UsdSemantics, UsdShade

from navverse.errors import SceneError
from navverse.scene.directory import SCENE_USD, read_scene, write_scene_dir
from navverse.scene.geometry import Scene
from navverse.scene.usd import export_usd, physics_materials, read_usd, scene_from_usd
from tests.navverse.scene.conftest import ROAD_FRICTION


@pytest.fixture(scope="module")
def scene_dir(tiny_scene: Scene, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("tiny_room")
    write_scene_dir(tiny_scene, out, bev=False)
    return out


def _angle_diff(a: float, b: float) -> float:
    return abs(math.remainder(a - b, math.tau))


def test_stage_metadata(scene_dir: Path) -> None:
    usd = read_usd(scene_dir / SCENE_USD)
    assert usd.up_axis == "Z"
    assert usd.meters_per_unit == 1.0
    assert usd.default_prim == "/World"
    stage = Usd.Stage.Open(str(scene_dir / SCENE_USD))
    physics_scene = UsdPhysics.Scene(stage.GetPrimAtPath("/World/PhysicsScene"))
    assert physics_scene
    assert tuple(physics_scene.GetGravityDirectionAttr().Get()) == (0.0, 0.0, -1.0)
    assert physics_scene.GetGravityMagnitudeAttr().Get() == pytest.approx(9.81)


def test_objects_round_trip(tiny_scene: Scene, scene_dir: Path) -> None:
    usd = read_usd(scene_dir / SCENE_USD)
    by_id = {o.instance_id: o for o in usd.objects}
    assert sorted(by_id) == [o.id for o in tiny_scene.annotations.objects]
    for obj in tiny_scene.objects:
        ann = obj.annotation
        read = by_id[ann.id]
        assert read.category == ann.category
        assert read.prim_path == ann.prim_path
        np.testing.assert_allclose(read.position, ann.center, atol=1e-6)
        assert _angle_diff(read.yaw, ann.yaw) < 1e-6
        np.testing.assert_allclose(read.size, ann.size, rtol=1e-6)
        assert read.labels == (ann.category,)
        assert read.physics_material == "/World/Physics/objects"
        assert read.static_friction == pytest.approx(0.6)
        np.testing.assert_allclose(read.mesh.vertices, obj.mesh.vertices, atol=1e-6)
        np.testing.assert_array_equal(read.mesh.faces, obj.mesh.faces)
        if obj.mesh.face_colors is None:
            assert read.mesh.face_colors is None
        else:
            np.testing.assert_array_equal(read.mesh.face_colors, obj.mesh.face_colors)


def test_surfaces_round_trip_with_friction_from_binding(tiny_scene: Scene, scene_dir: Path) -> None:
    usd = read_usd(scene_dir / SCENE_USD)
    assert [s.name for s in usd.surfaces] == [s.name for s in tiny_scene.surfaces]
    classes = tiny_scene.annotations.terrain_classes
    for surface, read in zip(tiny_scene.surfaces, usd.surfaces, strict=True):
        assert read.terrain_class == surface.terrain_class
        assert read.labels == (surface.terrain_class,)
        assert read.physics_material == f"/World/Physics/{surface.terrain_class}"
        assert read.static_friction == pytest.approx(classes[surface.terrain_class].friction, abs=1e-6)
        assert read.dynamic_friction == pytest.approx(classes[surface.terrain_class].friction, abs=1e-6)
        np.testing.assert_allclose(read.mesh.vertices, surface.mesh.vertices, atol=1e-6)
    road = next(s for s in usd.surfaces if s.name == "road_0")
    assert road.static_friction == pytest.approx(ROAD_FRICTION)
    np.testing.assert_array_equal(road.mesh.face_colors, tiny_scene.surfaces[-1].mesh.face_colors)


def test_physics_materials_lists_every_class_and_objects(tiny_scene: Scene, scene_dir: Path) -> None:
    materials = physics_materials(scene_dir / SCENE_USD)
    expected = {
        f"/World/Physics/{n}": tc.friction for n, tc in tiny_scene.annotations.terrain_classes.items()
    }
    expected["/World/Physics/objects"] = 0.6
    assert set(materials) == set(expected)
    for path, friction in expected.items():
        assert materials[path] == pytest.approx((friction, friction), abs=1e-6)


def test_schemas_for_physics_and_semantics(scene_dir: Path) -> None:
    stage = Usd.Stage.Open(str(scene_dir / SCENE_USD))
    floor = stage.GetPrimAtPath("/World/Terrain/floor")
    assert floor.HasAPI(UsdPhysics.CollisionAPI)
    assert UsdPhysics.MeshCollisionAPI(floor).GetApproximationAttr().Get() == "none"
    assert floor.GetAttribute("navverse:terrainClass").Get() == "floor"
    query = UsdSemantics.LabelsQuery("class", Usd.TimeCode.Default())
    assert list(query.ComputeUniqueDirectLabels(floor)) == ["floor"]
    chair = stage.GetPrimAtPath("/World/Objects/chair_0002")
    assert list(query.ComputeUniqueDirectLabels(chair)) == ["chair"]
    # Labels on the object's Xform are inherited by its mesh (what a segmentation renderer sees).
    assert list(query.ComputeUniqueInheritedLabels(chair.GetChild("mesh"))) == ["chair"]
    assert chair.GetAttribute("navverse:instanceId").Get() == 2
    assert chair.GetAttribute("xformOp:rotateZ").Get() == pytest.approx(math.degrees(-1.2))
    mesh = chair.GetChild("mesh")
    assert mesh.HasAPI(UsdPhysics.CollisionAPI)
    bound, _ = UsdShade.MaterialBindingAPI(mesh).ComputeBoundMaterial("physics")
    assert str(bound.GetPath()) == "/World/Physics/objects"
    assert UsdGeom.Mesh(floor).GetSubdivisionSchemeAttr().Get() == "none"


def test_friction_follows_the_binding_not_the_name(tiny_scene: Scene, tmp_path: Path) -> None:
    path = tmp_path / "scene.usdc"
    export_usd(tiny_scene, path)
    stage = Usd.Stage.Open(str(path))
    road_material = UsdShade.Material(stage.GetPrimAtPath("/World/Physics/road"))
    floor = stage.GetPrimAtPath("/World/Terrain/floor")
    UsdShade.MaterialBindingAPI(floor).Bind(road_material, UsdShade.Tokens.fallbackStrength, "physics")
    stage.Save()
    del stage
    floor_read = next(s for s in read_usd(path).surfaces if s.name == "floor")
    assert floor_read.physics_material == "/World/Physics/road"
    assert floor_read.static_friction == pytest.approx(ROAD_FRICTION)
    with pytest.raises(SceneError, match="friction"):
        scene_from_usd(path, tiny_scene.annotations)


def test_moved_object_is_detected(tiny_scene: Scene, tmp_path: Path) -> None:
    path = tmp_path / "scene.usdc"
    export_usd(tiny_scene, path)
    stage = Usd.Stage.Open(str(path))
    stage.GetPrimAtPath("/World/Objects/table_0003").GetAttribute("xformOp:translate").Set((1.0, 1.0, 0.0))
    stage.Save()
    del stage
    with pytest.raises(SceneError, match=r"object 3 \(table\) has moved"):
        scene_from_usd(path, tiny_scene.annotations)


def test_read_scene_rebuilds_the_scene(tiny_scene: Scene, scene_dir: Path) -> None:
    scene = read_scene(scene_dir)
    assert scene.annotations == tiny_scene.annotations
    assert [o.annotation for o in scene.objects] == list(tiny_scene.annotations.objects)
    original = tiny_scene.world_mesh()
    rebuilt = scene.world_mesh()
    np.testing.assert_allclose(rebuilt.mesh.vertices, original.mesh.vertices, atol=1e-5)
    np.testing.assert_array_equal(rebuilt.class_index, original.class_index)
    np.testing.assert_array_equal(rebuilt.instance_id, original.instance_id)


def test_export_is_byte_identical_and_can_overwrite_an_open_file(tiny_scene: Scene, tmp_path: Path) -> None:
    first, second = tmp_path / "a.usdc", tmp_path / "b.usdc"
    export_usd(tiny_scene, first)
    held_open = Usd.Stage.Open(str(first))
    export_usd(tiny_scene, first)  # a layer with this identifier is still alive
    export_usd(tiny_scene, second)
    assert first.read_bytes() == second.read_bytes()
    assert held_open.GetPrimAtPath("/World/Terrain/floor")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.usdc", "b.usdc"]  # no temporary left


def test_export_rejects_other_formats(tiny_scene: Scene, tmp_path: Path) -> None:
    with pytest.raises(SceneError, match=r"\.usdc"):
        export_usd(tiny_scene, tmp_path / "scene.usda")
    with pytest.raises(SceneError, match="does not exist"):
        export_usd(tiny_scene, tmp_path / "missing" / "scene.usdc")


def test_missing_usd_is_a_scene_error(tmp_path: Path) -> None:
    with pytest.raises(SceneError, match="navverse build"):
        read_usd(tmp_path / "scene.usdc")
