"""The ray-cast camera samples textures (orientation, bilinear filtering, repeat) and shows a sky."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pytest

from navverse.scene.compose import ObjectPart
from navverse.scene.geometry import MeshData, Scene, Surface, Texture
from navverse.sim import render as render_module
from navverse.sim.camera import CameraIntrinsics, look_at
from navverse.sim.render import Frame, SceneRenderer, Shading
from tests.scenes import box_part, quad, scene_of

SMALL = CameraIntrinsics.from_hfov(160, 120, 90.0)
FLAT = Shading(ambient=1.0, key=0.0, fill=0.0, headlight=0.0, fog=0.0, edge_shade=1.0, terrain_lighten=0.0)
EYE = np.array([0.0, 0.0, 1.0])
AHEAD = look_at(EYE, EYE + np.array([1.0, 0.0, 0.0]))  # optical x (image right) is world -y
QUAD_X = 4.0  # the textured quad: x = 4, y in [-1, 1] (left edge at y = +1), z in [0, 2]
RED, GREEN, BLUE, YELLOW = (220, 30, 30), (30, 200, 40), (40, 60, 210), (230, 210, 20)
UNIT_UVS = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))  # bottom-left, bottom-right, top-right, top-left


def quadrants(size: int = 8) -> np.ndarray:
    """A `size` x `size` image: red top-left, green top-right, blue bottom-left, yellow bottom-right."""
    image = np.empty((size, size, 3), dtype=np.uint8)
    half = size // 2
    image[:half, :half], image[:half, half:] = RED, GREEN
    image[half:, :half], image[half:, half:] = BLUE, YELLOW
    return image


def facing_quad(
    texture: Texture | None, uvs: Sequence[tuple[float, float]] = UNIT_UVS, *, x: float = QUAD_X
) -> MeshData:
    """The quad at `x` facing the camera, corners bottom-left, bottom-right, top-right, top-left as seen
    from it, with `uvs` at those corners (untextured without `texture`)."""
    vertices = np.array([[x, 1.0, 0.0], [x, -1.0, 0.0], [x, -1.0, 2.0], [x, 1.0, 2.0]])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    if texture is None:
        return MeshData(vertices, faces)
    corner_uvs = np.asarray(uvs, dtype=np.float32)[faces]
    return MeshData(vertices, faces, None, corner_uvs, np.zeros(2, np.int16), (texture,))


def quad_scene(mesh: MeshData, objects: Sequence[ObjectPart] = (), *, scene_type: str = "indoor") -> Scene:
    """A floor, the quad (terrain class ``wall``) and `objects`."""
    surfaces = [Surface("floor", "floor", quad(-1.0, -3.0, 6.0, 3.0, 0.0)), Surface("facade", "wall", mesh)]
    return scene_of(surfaces, objects, scene_id="textured", scene_type=scene_type)


def pixel_of(point: Sequence[float], pose: np.ndarray = AHEAD) -> tuple[int, int]:
    """(row, col) of the pixel a world point projects to."""
    local = np.linalg.inv(pose) @ np.append(point, 1.0)
    u, v = SMALL.project(local[:3])
    return math.floor(v), math.floor(u)


def quad_point(u: float, v: float) -> tuple[float, float, float]:
    """World point of the unit-UV quad at texture coordinates (u, v)."""
    return (QUAD_X, 1.0 - 2.0 * u, 2.0 * v)


def render(scene: Scene, pose: np.ndarray = AHEAD, shading: Shading = FLAT) -> Frame:
    return SceneRenderer(scene, intrinsics=SMALL, shading=shading).render(pose)


@pytest.fixture(scope="module")
def quadrant_frame() -> Frame:
    return render(quad_scene(facing_quad(Texture("quadrants", quadrants()))))


@pytest.mark.parametrize(
    ("uv", "color"),
    [((0.25, 0.75), RED), ((0.75, 0.75), GREEN), ((0.25, 0.25), BLUE), ((0.75, 0.25), YELLOW)],
)
def test_texels_show_up_right_way_round(quadrant_frame: Frame, uv: tuple[float, float], color) -> None:
    # Row 0 of the image is the top (v = 1), column 0 the left (u = 0).
    row, col = pixel_of(quad_point(*uv))
    assert quadrant_frame.terrain[row, col] == 1  # the quad
    assert tuple(quadrant_frame.rgb[row, col]) == color


def test_texture_fills_the_whole_quad(quadrant_frame: Frame) -> None:
    on_quad = quadrant_frame.terrain == 1
    colors = {tuple(c) for c in quadrant_frame.rgb[on_quad]}
    # Flat-coloured blocks: only the one-texel seams between them blend.
    counts = {
        c: int((quadrant_frame.rgb[on_quad] == c).all(axis=1).sum()) for c in (RED, GREEN, BLUE, YELLOW)
    }
    assert min(counts.values()) > 0.15 * on_quad.sum()
    assert len(colors) > 4  # the seams are bilinear blends


def test_bilinear_filtering_follows_the_texel_centres() -> None:
    # Two texels, black and white: with repeat, brightness is a triangle wave in u, 0 at u = 0.25,
    # 255 at u = 0.75 and 127.5 at u = 0 and 0.5 (where it wraps round).
    image = np.array([[[0, 0, 0], [255, 255, 255]]], dtype=np.uint8)
    frame = render(quad_scene(facing_quad(Texture("ramp", image))))
    row = pixel_of(quad_point(0.5, 0.5))[0]
    cols = np.flatnonzero(frame.terrain[row] == 1)
    assert len(cols) > 30
    k = SMALL
    y_world = -(cols + 0.5 - k.cx) / k.fx * (QUAD_X - EYE[0])  # where each pixel's ray meets the quad
    u = (1.0 - y_world) / 2.0
    white = 1.0 - 2.0 * np.abs(np.mod(u - 0.25, 1.0) - 0.5)
    np.testing.assert_allclose(frame.rgb[row, cols, 0], 255.0 * white, atol=1.0)
    assert (frame.rgb[row, cols, 0] == frame.rgb[row, cols, 2]).all()


def test_uvs_outside_the_unit_square_repeat(quadrant_frame: Frame) -> None:
    texture = Texture("quadrants", quadrants())
    shifted = [(u - 3.0, v + 2.0) for u, v in UNIT_UVS]  # whole-number shift: the same image
    frame = render(quad_scene(facing_quad(texture, shifted)))
    np.testing.assert_allclose(frame.rgb, quadrant_frame.rgb, atol=1)
    tiled = [(2.0 * u, 2.0 * v) for u, v in UNIT_UVS]  # two by two copies of the image
    frame = render(quad_scene(facing_quad(texture, tiled)))
    for tile_u in (0.0, 0.5):
        for tile_v in (0.0, 0.5):
            for (u, v), color in [((0.25, 0.75), RED), ((0.75, 0.75), GREEN), ((0.25, 0.25), BLUE)]:
                row, col = pixel_of(quad_point(tile_u + u / 2, tile_v + v / 2))
                assert tuple(frame.rgb[row, col]) == color


def test_shading_multiplies_the_texel_colour() -> None:
    dim = Shading(ambient=0.5, key=0.0, fill=0.0, headlight=0.0, fog=0.0, edge_shade=1.0, terrain_lighten=0.0)
    frame = render(quad_scene(facing_quad(Texture("quadrants", quadrants()))), shading=dim)
    row, col = pixel_of(quad_point(0.75, 0.25))
    np.testing.assert_allclose(frame.rgb[row, col], 0.5 * np.array(YELLOW), atol=0.51)


def _textured_box(size: float = 0.6) -> MeshData:
    """A box whose faces all show one 2 x 2 texture of two colours, each face's UVs the unit square."""
    box = MeshData.box((size, size, size))
    uvs = np.array([[[0.25, 0.25], [0.75, 0.25], [0.75, 0.75]]], dtype=np.float32).repeat(box.num_faces, 0)
    image = np.array([[RED, RED], [RED, RED]], dtype=np.uint8)
    return MeshData(
        box.vertices, box.faces, None, uvs, np.zeros(box.num_faces, np.int16), (Texture("red", image),)
    )


def test_several_textures_share_one_pool(quadrant_frame: Frame) -> None:
    # A textured object (after the surfaces in face order, its texture second in the pool) in front of
    # the textured quad: both sample their own texture.
    box = ObjectPart("crate", _textured_box(), (2.0, -0.6, 1.0), yaw=0.4)
    frame = render(quad_scene(facing_quad(Texture("quadrants", quadrants())), [box]))
    crate = frame.semantic == 1
    assert crate.sum() > 100
    assert (frame.rgb[crate] == RED).all()
    row, col = pixel_of(quad_point(0.25, 0.75))
    assert frame.terrain[row, col] == 1 and tuple(frame.rgb[row, col]) == RED
    row, col = pixel_of(quad_point(0.25, 0.25))
    assert tuple(frame.rgb[row, col]) == BLUE


def test_hits_sampled_in_chunks_give_the_same_frame(monkeypatch: pytest.MonkeyPatch) -> None:
    # The renderer samples textured hits a chunk at a time; chunks far smaller than the hits (and
    # spanning both textures) must give the same bytes as one chunk.
    box = ObjectPart("crate", _textured_box(), (2.0, -0.6, 1.0), yaw=0.4)
    scene = quad_scene(facing_quad(Texture("quadrants", quadrants())), [box])
    whole = render(scene)
    monkeypatch.setattr(render_module, "_CHUNK", 37)
    chunked = render(scene)
    textured = (whole.terrain == 1) | (whole.semantic == 1)
    assert textured.sum() > 1000  # dozens of chunks
    np.testing.assert_array_equal(chunked.rgb, whole.rgb)
    assert (chunked.rgb[chunked.semantic == 1] == RED).all()
    for uv, color in [((0.25, 0.75), RED), ((0.25, 0.25), BLUE)]:  # the quad beside the crate
        row, col = pixel_of(quad_point(*uv))
        assert chunked.terrain[row, col] == 1 and tuple(chunked.rgb[row, col]) == color


def test_untextured_faces_are_unchanged() -> None:
    # The same scene with and without the quad's texture, under the default (lit, fogged) shading:
    # everything off the quad is byte-identical, labels and depth everywhere.
    objects = [box_part("chair", (2.0, 0.6, 0.5), (0.4, 0.4, 1.0), rgb=(200, 40, 40))]
    pose = look_at((-0.5, -1.5, 1.6), (3.0, 0.0, 0.8))
    textured = render(quad_scene(facing_quad(Texture("q", quadrants())), objects), pose, Shading())
    plain = render(quad_scene(facing_quad(None), objects), pose, Shading())
    on_quad = textured.terrain == 1
    assert 500 < on_quad.sum() < on_quad.size - 500
    assert (textured.rgb[~on_quad] == plain.rgb[~on_quad]).all()
    assert (textured.rgb[on_quad] != plain.rgb[on_quad]).any(axis=-1).mean() > 0.9
    for name in ("depth", "semantic", "terrain"):
        assert getattr(textured, name).tobytes() == getattr(plain, name).tobytes()
    # A mesh that carries UVs but no textured face renders exactly like one without.
    bare = facing_quad(None)
    texture = (Texture("q", quadrants()),)
    untextured_uvs = MeshData(
        bare.vertices, bare.faces, None, np.zeros((2, 3, 2), np.float32), np.full(2, -1, np.int16), texture
    )
    same = render(quad_scene(untextured_uvs, objects), pose, Shading())
    assert same.rgb.tobytes() == plain.rgb.tobytes()


# ---------------------------------------------------------------------- sky

SKY = Shading(sky=True)
HORIZON, ZENITH = np.array(SKY.sky_horizon, float), np.array(SKY.sky_zenith, float)


def _empty_scene(scene_type: str = "indoor") -> Scene:
    return scene_of(
        [Surface("floor", "floor", quad(-1.0, -1.0, 1.0, 1.0, 0.0))], scene_id="sky", scene_type=scene_type
    )


def _expected_sky(renderer: SceneRenderer, pose: np.ndarray) -> np.ndarray:
    """Sky colour of every pixel, from its world ray's elevation."""
    directions = SMALL.ray_directions() @ pose[:3, :3].T
    sine = np.clip(directions[..., 2] / np.linalg.norm(directions, axis=-1), 0.0, 1.0)
    return HORIZON + sine[..., None] * (ZENITH - HORIZON)


def test_sky_looking_up_is_the_zenith_colour() -> None:
    renderer = SceneRenderer(_empty_scene(), intrinsics=SMALL, shading=SKY)
    eye = np.array([0.0, 0.0, 5.0])
    pose = look_at(eye, eye + np.array([0.0, 0.0, 1.0]), up=(1.0, 0.0, 0.0))
    frame = renderer.render(pose)
    assert not frame.hit.any()
    assert (frame.depth == 0.0).all() and (frame.semantic == 0).all() and (frame.terrain == -1).all()
    np.testing.assert_allclose(frame.rgb[60, 80], ZENITH, atol=1.0)
    # Corners are 37 degrees off the zenith: between the two colours, nearer the zenith.
    corner = frame.rgb[0, 0].astype(float)
    assert ZENITH[2] < corner[2] < HORIZON[2] and abs(corner[0] - ZENITH[0]) < abs(corner[0] - HORIZON[0])
    np.testing.assert_allclose(frame.rgb, _expected_sky(renderer, pose), atol=0.51)


def test_sky_grades_to_the_horizon_without_fog_or_outlines() -> None:
    # Default (lit, fogged, outlined) shading with the sky: the floor is hit below the horizon, the
    # sky above it shows exactly the gradient; below the horizon, past the floor, the horizon colour.
    renderer = SceneRenderer(_empty_scene(), intrinsics=SMALL, shading=SKY)
    eye = np.array([0.0, 0.0, 0.5])
    pose = look_at(eye, eye + np.array([1.0, 0.0, -0.15]))
    frame = renderer.render(pose)
    sky = ~frame.hit
    assert frame.hit.any() and sky[0].all()
    np.testing.assert_allclose(frame.rgb[sky], _expected_sky(renderer, pose)[sky], atol=0.51)
    column = frame.rgb[: np.argmax(frame.hit[:, 80]), 80, 2].astype(int)
    assert (np.diff(column) >= 0).all() and column[0] < column[-1]  # bluer upwards
    down = SceneRenderer(_empty_scene(), intrinsics=SMALL, shading=SKY, hidden_classes=("floor",))
    below = down.render(look_at(eye, eye + np.array([1.0, 0.0, -1.0])))
    assert (below.rgb[-1] == HORIZON).all()


def test_default_shading_has_a_sky_outdoors_only() -> None:
    assert not SceneRenderer(_empty_scene("indoor"), intrinsics=SMALL).shading.sky
    assert SceneRenderer(_empty_scene("outdoor"), intrinsics=SMALL).shading.sky
    assert SceneRenderer(_empty_scene("i2o"), intrinsics=SMALL).shading.sky
    indoor = SceneRenderer(_empty_scene("indoor"), intrinsics=SMALL, shading=Shading())
    frame = indoor.render(look_at(EYE, EYE + np.array([0.0, 0.0, 1.0]), up=(1.0, 0.0, 0.0)))
    assert (frame.rgb == Shading().background).all()
    with pytest.raises(ValueError, match="sky_zenith"):
        Shading(sky=True, sky_zenith=(0, 0, 300))
