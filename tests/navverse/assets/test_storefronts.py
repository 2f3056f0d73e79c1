"""Procedural storefronts: categories, designs, exact sizes, the textured sign and OSM tag mapping."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

from navverse.assets.errors import AssetSizeError, UnknownCategoryError
from navverse.assets.facade import storefront_signs
from navverse.assets.facade.storefronts import (
    DESIGNS_PER_CATEGORY,
    PLACE_CATEGORIES,
    Storefront,
    design_count,
    place_category,
    storefront,
)
from navverse.scene.geometry import MeshData
from navverse.scene.naming import is_identifier


def _normals(mesh: MeshData) -> np.ndarray:
    tri = mesh.vertices[mesh.faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def _is_closed(mesh: MeshData) -> bool:
    """Every directed edge occurs once and its reverse occurs too (closed, consistently wound parts)."""
    edges = mesh.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    n = mesh.num_vertices
    codes = edges[:, 0] * n + edges[:, 1]
    reverse = edges[:, 1] * n + edges[:, 0]
    return np.unique(codes).size == codes.size and bool(np.isin(reverse, codes).all())


def _fingerprint(front: Storefront) -> str:
    mesh = front.mesh
    digest = hashlib.sha1(mesh.vertices.tobytes())
    for array in (mesh.faces, mesh.face_colors, mesh.face_uvs, mesh.face_texture, front.sign_image):
        digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


def test_category_and_design_counts() -> None:
    assert len(PLACE_CATEGORIES) >= 17
    assert len(set(PLACE_CATEGORIES)) == len(PLACE_CATEGORIES)
    assert design_count() == len(PLACE_CATEGORIES) * DESIGNS_PER_CATEGORY >= 101
    assert set(storefront_signs.ICONS) == set(PLACE_CATEGORIES)


@pytest.mark.parametrize("category", PLACE_CATEGORIES)
def test_every_design_builds_closed_centred_and_sized(category: str) -> None:
    fingerprints = set()
    for design in range(DESIGNS_PER_CATEGORY):
        front = storefront(category, np.random.default_rng(5), design=design, width=5.5, height=3.6)
        mesh = front.mesh
        assert (front.category, front.design) == (category, design)
        assert _is_closed(mesh)
        lo, hi = mesh.bounds()
        np.testing.assert_allclose(lo + hi, 0.0, atol=1e-9)
        np.testing.assert_allclose(hi - lo, front.size, atol=1e-9)
        assert front.size[0] == pytest.approx(5.5)
        assert front.size[2] == pytest.approx(3.6)
        assert 0.4 <= front.size[1] <= 2.0
        assert mesh.face_colors is not None and mesh.textured
        glass = front.glass_faces
        assert glass.shape == (mesh.num_faces,) and glass.any()
        assert np.unique(mesh.face_colors[glass], axis=0).shape[0] == 1
        fingerprints.add(_fingerprint(front))
    assert len(fingerprints) == DESIGNS_PER_CATEGORY


@pytest.mark.parametrize("category", ["cafe", "pharmacy", "bakery", "hairdresser", "shop"])
def test_only_the_sign_front_is_textured_and_reads_from_the_front(category: str) -> None:
    for design in range(DESIGNS_PER_CATEGORY):
        front = storefront(category, np.random.default_rng(design), design=design)
        mesh = front.mesh
        assert len(mesh.textures) == 1 and is_identifier(mesh.textures[0].name)
        textured = mesh.face_texture == 0
        assert textured.sum() == 2
        assert (mesh.face_texture[~textured] == -1).all()
        assert (_normals(mesh)[textured, 1] > 0.9).all()
        corners = mesh.vertices[mesh.faces[textured]]
        uv = mesh.face_uvs[textured]
        cx, cy, cz = front.sign_center
        w, h = front.sign_size
        np.testing.assert_allclose(corners[..., 1], cy, atol=1e-9)
        # seen from +y, +x is the reader's left: u = 0 at the largest x, v = 0 at the bottom
        np.testing.assert_allclose(uv[..., 0], (cx + 0.5 * w - corners[..., 0]) / w, atol=1e-5)
        np.testing.assert_allclose(uv[..., 1], (corners[..., 2] - (cz - 0.5 * h)) / h, atol=1e-5)
        assert {float(u) for u in uv[..., 0].ravel()} == {0.0, 1.0}
        assert cy > front.entrance[1]  # the board stands proud of the facade plane


def test_sign_image_shows_text_and_icon() -> None:
    front = storefront("cafe", np.random.default_rng(1), name="Blue Bottle", design=0, width=6.0)
    image = front.sign_image
    assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3
    w, h = front.sign_size
    assert image.shape[1] / image.shape[0] == pytest.approx(w / h, rel=0.02)
    background = image[2, image.shape[1] // 2]
    ink = (np.abs(image.astype(int) - background).sum(axis=2) > 60).mean(axis=0)
    third = image.shape[1] // 3
    assert ink[third : 2 * third].mean() > 0.03  # lettering in the middle of the board
    assert ink[: image.shape[0]].mean() > 0.03  # the icon at the left end
    blank = storefront_signs.sign_image(
        "", "cafe", background=(10, 10, 10), foreground=(250, 250, 250), aspect=6.0, icons=0
    )
    assert (blank == 10).all()
    text_only = storefront_signs.sign_image(
        "Blue Bottle", "cafe", background=(10, 10, 10), foreground=(250, 250, 250), aspect=6.0, icons=0
    )
    assert (text_only > 200).all(axis=2).mean() > 0.03


def test_sign_text_is_not_mirrored() -> None:
    """Text is drawn left to right: the first letter's ink starts left of the last letter's."""
    image = storefront_signs.sign_image(
        "I" + " " * 10 + "WWWW", "shop", background=(0, 0, 0), foreground=(255, 255, 255), aspect=8.0, icons=0
    )
    ink = (image > 128).any(axis=2).sum(axis=0)
    columns = np.flatnonzero(ink)
    left_half, right_half = ink[: image.shape[1] // 2].sum(), ink[image.shape[1] // 2 :].sum()
    assert columns.size and right_half > 2 * left_half  # the wide "WWWW" is on the right


def test_same_seed_same_storefront_and_name_changes_texture() -> None:
    a = storefront("bakery", np.random.default_rng(42))
    b = storefront("bakery", np.random.default_rng(42))
    assert _fingerprint(a) == _fingerprint(b)
    assert a.mesh.textures[0].name == b.mesh.textures[0].name
    assert (a.name, a.design, a.size, a.entrance) == (b.name, b.design, b.size, b.entrance)
    assert 0 <= a.design < DESIGNS_PER_CATEGORY and 4.0 <= a.size[0] <= 8.0
    c = storefront("bakery", np.random.default_rng(42), name="Crumbs & Co")
    assert c.name == "Crumbs & Co"
    assert c.mesh.textures[0].name != a.mesh.textures[0].name
    assert not np.array_equal(c.sign_image, a.sign_image) or c.sign_image.shape != a.sign_image.shape
    joined = MeshData.concatenate([a.mesh, b.mesh.transformed((10.0, 0.0, 0.0)), c.mesh])
    assert len(joined.textures) == 2
    assert (joined.face_texture >= 0).sum() == 6


def test_entrance_is_the_door_centre_on_the_front_plane() -> None:
    for design in range(DESIGNS_PER_CATEGORY):
        front = storefront("supermarket", np.random.default_rng(design), design=design, width=6.0)
        mesh = front.mesh
        ex, ey, ez = front.entrance
        _, depth, height = front.size
        assert ez == pytest.approx(-0.5 * height)
        assert -0.5 * depth < ey < 0.5 * depth
        # the facade panel's front faces lie in the entrance plane
        normals = _normals(mesh)
        tri_y = mesh.vertices[mesh.faces][..., 1]
        on_plane = (normals[:, 1] > 0.99) & (np.abs(tri_y - ey) < 1e-9).all(axis=1)
        assert on_plane.sum() >= 4
        # the doorway in front of and just behind that plane is free up to 2 m
        v = mesh.vertices
        inside = (np.abs(v[:, 0] - ex) < 0.35) & (v[:, 1] > ey - 0.05) & (v[:, 1] < ey + 1.5)
        assert not (inside & (v[:, 2] < ez + 2.0)).any()
        # and the door leaf stands right behind it
        behind = (np.abs(v[:, 0] - ex) < 0.45) & (v[:, 1] < ey - 0.05) & (v[:, 1] > ey - 0.2)
        assert (behind & (v[:, 2] < ez + 2.0)).any()


@pytest.mark.parametrize(
    ("tags", "expected"),
    [
        ({"amenity": "restaurant", "name": "Chez Nous"}, "restaurant"),
        ({"amenity": "pub"}, "bar"),
        ({"amenity": "bureau_de_change"}, "bank"),
        ({"amenity": "dentist"}, "clinic"),
        ({"shop": "chemist"}, "pharmacy"),
        ({"shop": "kiosk"}, "convenience"),
        ({"shop": "pastry"}, "bakery"),
        ({"shop": "shoes"}, "clothes"),
        ({"shop": "mobile_phone"}, "electronics"),
        ({"shop": "doityourself"}, "hardware"),
        ({"amenity": "cafe", "shop": "bakery"}, "cafe"),
        ({"amenity": "parking", "shop": "bakery"}, "bakery"),
        ({"shop": "bicycle"}, "shop"),
        ({"shop": "vacant"}, None),
        ({"amenity": "parking"}, None),
        ({"highway": "bus_stop"}, None),
        ({}, None),
    ],
)
def test_place_category(tags: dict[str, str], expected: str | None) -> None:
    assert place_category(tags) == expected
    if expected is not None:
        assert expected in PLACE_CATEGORIES


def test_bad_arguments_raise() -> None:
    rng = np.random.default_rng(0)
    with pytest.raises(UnknownCategoryError):
        storefront("spaceport", rng)
    with pytest.raises(AssetSizeError):
        storefront("cafe", rng, width=2.0)
    with pytest.raises(AssetSizeError):
        storefront("cafe", rng, height=2.5)
    with pytest.raises(ValueError, match="design"):
        storefront("cafe", rng, design=DESIGNS_PER_CATEGORY)
