"""The texture contract of MeshData: UVs and texture indices are checked, concatenation merges
textures by name and keeps every face's texture and UVs."""

from __future__ import annotations

import numpy as np
import pytest

from navverse.scene.geometry import MeshData, Texture


def _image(value: int) -> np.ndarray:
    return np.full((4, 4, 3), value, dtype=np.uint8)


def _textured(texture: Texture, first: int = 2) -> MeshData:
    box = MeshData.box((1.0, 1.0, 1.0))
    uvs = np.random.default_rng(0).uniform(size=(12, 3, 2))
    index = np.r_[np.zeros(first, int), np.full(12 - first, -1)]
    return MeshData(box.vertices, box.faces, None, uvs, index, (texture,))


def test_concatenation_merges_textures_by_name_and_keeps_uvs() -> None:
    brick, sign = Texture("brick", _image(10)), Texture("sign", _image(200))
    a, b = _textured(brick), _textured(sign, first=4)
    plain = MeshData.box((2.0, 2.0, 2.0))
    joined = MeshData.concatenate([a, plain, b, a.transformed((3.0, 0.0, 0.0), 0.5)])
    assert [t.name for t in joined.textures] == ["brick", "sign"]
    expected = np.r_[a.face_texture, np.full(12, -1), np.where(b.face_texture >= 0, 1, -1), a.face_texture]
    np.testing.assert_array_equal(joined.face_texture, expected)
    np.testing.assert_array_equal(joined.face_uvs[:12], a.face_uvs)
    np.testing.assert_array_equal(joined.face_uvs[24:36], b.face_uvs)
    assert joined.textured and not plain.textured
    assert MeshData.concatenate([plain, plain]).face_texture is None


def test_one_name_must_hold_one_image() -> None:
    with pytest.raises(ValueError, match="both named 'brick'"):
        MeshData.concatenate([_textured(Texture("brick", _image(1))), _textured(Texture("brick", _image(2)))])


@pytest.mark.parametrize(
    ("uvs", "index", "textures", "message"),
    [
        (np.zeros((12, 3, 2)), None, (), "come together"),
        (np.zeros((12, 3, 2)), np.full(12, 1), (Texture("t", _image(0)),), r"in \[-1, 1\)"),
        (np.zeros((11, 3, 2)), np.full(12, 0), (Texture("t", _image(0)),), "shape"),
        (None, None, (Texture("t", _image(0)),), "need face_uvs"),
    ],
)
def test_bad_texture_arrays_are_refused(uvs, index, textures, message) -> None:
    box = MeshData.box((1.0, 1.0, 1.0))
    with pytest.raises(ValueError, match=message):
        MeshData(box.vertices, box.faces, None, uvs, index, textures)


def test_a_texture_is_an_rgb_uint8_image_with_an_identifier_name() -> None:
    with pytest.raises(ValueError, match="identifier"):
        Texture("not a name", _image(0))
    with pytest.raises(ValueError, match="shape"):
        Texture("gray", np.zeros((4, 4), np.uint8))
    with pytest.raises(ValueError, match="uint8"):
        Texture("float", np.zeros((4, 4, 3), np.float32))
