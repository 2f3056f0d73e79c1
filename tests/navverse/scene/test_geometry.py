from __future__ import annotations

import math

import numpy as np
import pytest

from navverse.scene.colors import default_color
from navverse.scene.geometry import MeshData, Scene, SceneObject, Surface
from navverse.scene.naming import sanitize_identifier
from tests.navverse.scene.conftest import OBJECTS


def test_mesh_validation() -> None:
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        MeshData(np.zeros((3, 2)), np.zeros((1, 3), dtype=int))
    with pytest.raises(ValueError, match="face indices"):
        MeshData(np.zeros((3, 3)), np.array([[0, 1, 3]]))
    with pytest.raises(ValueError, match="integers"):
        MeshData(np.zeros((3, 3)), np.array([[0.0, 1.0, 2.0]]))
    with pytest.raises(ValueError, match="face_colors"):
        MeshData(np.zeros((3, 3)), np.array([[0, 1, 2]]), np.zeros((2, 3), dtype=np.uint8))


def test_mesh_arrays_are_copied_and_read_only() -> None:
    vertices = np.eye(3)
    mesh = MeshData(vertices, np.array([[0, 1, 2]], dtype=np.int32))
    vertices[0, 0] = 5.0
    assert mesh.vertices[0, 0] == 1.0
    assert mesh.faces.dtype == np.int64
    with pytest.raises(ValueError):
        mesh.vertices[0, 0] = 2.0


def test_transformed_rotates_about_z_then_translates() -> None:
    mesh = MeshData(np.array([[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]), np.array([[0, 1, 2]]))
    moved = mesh.transformed((10.0, 20.0, 30.0), math.pi / 2)
    np.testing.assert_allclose(moved.vertices, [[10, 21, 30], [8, 20, 30], [10, 20, 33]], atol=1e-12)


def test_concatenate_reindexes_faces_and_keeps_colors() -> None:
    a = MeshData.box((1, 1, 1))
    b = MeshData.box((2, 2, 2), center=(5, 0, 0))
    joined = MeshData.concatenate([a, b])
    assert (joined.num_vertices, joined.num_faces) == (16, 24)
    np.testing.assert_array_equal(joined.faces[12:], b.faces + 8)
    np.testing.assert_allclose(joined.bounds()[1], [6, 1, 1])
    colored = MeshData(a.vertices, a.faces, np.full((12, 3), 7, dtype=np.uint8))
    with pytest.raises(ValueError, match="face_colors"):
        MeshData.concatenate([colored, b])
    assert MeshData.concatenate([colored, colored]).face_colors.shape == (24, 3)
    assert MeshData.concatenate([]).num_faces == 0


def test_box_faces_point_outwards() -> None:
    box = MeshData.box((2.0, 3.0, 4.0), center=(1.0, 1.0, 1.0))
    tri = box.vertices[box.faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    outward = tri.mean(axis=1) - np.array([1.0, 1.0, 1.0])
    assert (np.einsum("ij,ij->i", normals, outward) > 0).all()
    np.testing.assert_allclose(box.bounds()[0], [0.0, -0.5, -1.0])


def test_surface_name_must_be_identifier() -> None:
    with pytest.raises(ValueError, match="identifier"):
        Surface("road 1", "road", MeshData.box((1, 1, 1)))
    assert sanitize_identifier("road 1") == "road_1"
    assert sanitize_identifier("3d-room") == "_3d_room"


def test_scene_validates_objects_and_classes(tiny_scene: Scene) -> None:
    with pytest.raises(ValueError, match=r"annotations\.objects"):
        Scene(tiny_scene.annotations, tiny_scene.surfaces, tiny_scene.objects[::-1])
    lava = Surface("lava_0", "lava", MeshData.box((1, 1, 1)))
    with pytest.raises(ValueError, match="lava"):
        Scene(tiny_scene.annotations, (*tiny_scene.surfaces, lava), tiny_scene.objects)
    with pytest.raises(ValueError, match="unique"):
        Scene(tiny_scene.annotations, (*tiny_scene.surfaces, tiny_scene.surfaces[0]), tiny_scene.objects)


def test_world_mesh_labels(tiny_scene: Scene) -> None:
    labeled = tiny_scene.world_mesh(exclude_classes=("ceiling", "not_in_this_scene"))
    assert labeled.class_names == ("floor", "wall", "ceiling", "road")
    assert labeled.class_mask("floor").sum() == 2
    assert labeled.class_mask("wall").sum() == 24
    assert labeled.class_mask("ceiling").sum() == 0
    assert labeled.object_mask.sum() == 36
    assert (labeled.class_index[labeled.object_mask] == -1).all()
    assert (labeled.instance_id[~labeled.object_mask] == 0).all()
    for object_id, _category, center, size, yaw in OBJECTS:
        vertices = labeled.mesh.vertices[np.unique(labeled.mesh.faces[labeled.instance_id == object_id])]
        np.testing.assert_allclose(vertices.mean(axis=0), center, atol=1e-12)
        # Rotating back by -yaw recovers the axis-aligned box of the given size.
        local = (vertices - center) @ np.array(
            [[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]]
        )
        np.testing.assert_allclose(np.abs(local).max(axis=0), np.array(size) / 2, atol=1e-12)
    no_objects = tiny_scene.world_mesh(include_objects=False)
    assert no_objects.mesh.num_faces == 2 + 24 + 2 + 2


def test_scene_object_world_mesh(tiny_scene: Scene) -> None:
    obj: SceneObject = tiny_scene.objects[0]
    lo, hi = obj.world_mesh().bounds()
    np.testing.assert_allclose((lo + hi) / 2, obj.annotation.center, atol=1e-12)


def test_default_color_is_stable_and_distinct() -> None:
    assert default_color("chair") == default_color("chair")
    assert default_color("chair") != default_color("table")
    assert all(0 <= c <= 255 for c in default_color("anything"))
