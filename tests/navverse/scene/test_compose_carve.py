"""Cutting keeps colours and textures: carve and remove_inside on textured solids."""

from __future__ import annotations

import numpy as np
import pytest

from navverse.errors import SceneError
from navverse.scene.compose import carve, remove_inside
from navverse.scene.geometry import MeshData, Surface, Texture
from tests.scenes import scene_of


def _planar_uv_box(size: float = 2.0) -> MeshData:
    """A closed box whose every face is textured with UV = (x, z) / size (planar mapping)."""
    box = MeshData.box((size, size, size), center=(0.0, 0.0, size / 2))
    uvs = np.stack([box.vertices[box.faces][..., 0], box.vertices[box.faces][..., 2]], axis=-1) / size
    image = np.zeros((4, 4, 3), np.uint8)
    image[..., 0] = 200
    colors = np.full((box.num_faces, 3), 90, np.uint8)
    return MeshData(
        box.vertices, box.faces, colors, uvs.astype(np.float32), np.zeros(box.num_faces, np.int16),
        (Texture("brick", image),),
    )  # fmt: skip


def _notch() -> MeshData:
    return MeshData.box((0.6, 0.6, 0.6), center=(1.0, 1.0, 1.0))  # over the vertical edge at x = y = 1


def test_carve_removes_the_overlap_and_interpolates_uvs() -> None:
    box = _planar_uv_box()
    carved, removed = carve(box, _notch())
    assert removed == pytest.approx(0.3 * 0.3 * 0.6, rel=1e-6)  # x, y in [0.7, 1]; z in [0.7, 1.3]
    assert carved.textured and carved.textures[0].name == "brick"
    kept = carved.face_texture >= 0
    # every surviving textured corner still has the planar UV of its position
    corners = carved.vertices[carved.faces[kept]]
    expected = np.stack([corners[..., 0], corners[..., 2]], axis=-1) / 2.0
    np.testing.assert_allclose(carved.face_uvs[kept], expected, atol=1e-5)
    # the new faces of the notch are untextured and take the first colour
    assert (~kept).any()
    assert (carved.face_colors[~kept] == 90).all()


def test_carve_refuses_an_open_surface() -> None:
    sheet = MeshData(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]]), np.array([[0, 1, 2]]))
    with pytest.raises(SceneError, match="closed"):
        carve(sheet, _notch())


def test_remove_inside_keeps_textures_of_cut_surfaces() -> None:
    scene = scene_of([Surface("block", "building", _planar_uv_box())], scene_id="carve")
    cut = remove_inside(scene, _notch())
    mesh = cut.surfaces[0].mesh
    assert mesh.textured
    assert mesh.num_faces > 12  # the notch added faces
