from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from navverse.errors import SceneError
from navverse.scene.bev import BevOverlay, BevRaster, auto_meters_per_pixel, raster_bev, render_bev
from navverse.scene.colors import default_color, lighten
from navverse.scene.geometry import MeshData, Scene, Surface
from tests.navverse.scene.conftest import FLOOR_POINT, OBJECTS, ROAD_POINT, WALL_POINT
from tests.scenes import quad, scene_of

MPP = 0.02


@pytest.fixture(scope="module")
def bev(tiny_scene: Scene, tmp_path_factory: pytest.TempPathFactory) -> tuple[np.ndarray, object]:
    path = tmp_path_factory.mktemp("bev") / "bev.png"
    overlay = BevOverlay("path", np.array([[[1.0, 7.0], [9.5, 7.0]]]), color=(0.0, 0.0, 1.0), linewidth=3.0)
    info = render_bev(tiny_scene, path, meters_per_pixel=MPP, overlays=[overlay])
    image = np.asarray(Image.open(path).convert("RGB"))
    return image, info


def _pixel(image: np.ndarray, info: object, xy: tuple[float, float]) -> np.ndarray:
    row, col = info.world_to_pixel(xy)
    return image[row, col].astype(int)


def _distance(a: np.ndarray, b: tuple[int, int, int]) -> float:
    return float(np.linalg.norm(a - np.array(b)))


def test_png_size_matches_info(bev: tuple[np.ndarray, object]) -> None:
    image, info = bev
    assert image.shape[:2] == info.image_shape
    assert info.raster_shape == (600, 700)  # 12 m x 14 m at 2 cm
    assert info.image_shape[1] > info.image_shape[0]  # the scene is wider than tall
    row, col = info.raster_offset
    assert row + 600 <= image.shape[0] and col + 700 <= image.shape[1]


def test_pixels_take_their_terrain_class_colour(tiny_scene: Scene, bev: tuple[np.ndarray, object]) -> None:
    image, info = bev
    classes = tiny_scene.annotations.terrain_classes
    for point, name in ((FLOOR_POINT, "floor"), (WALL_POINT, "wall"), (ROAD_POINT, "road")):
        color = _pixel(image, info, point)
        nearest = min(classes, key=lambda n: _distance(color, classes[n].color))
        assert nearest == name, (point, color)
        assert _distance(color, classes[name].color) < 6, (name, color)
    # The ceiling (show_in_bev=False) does not hide the floor, and outside the scene is white.
    assert _distance(_pixel(image, info, FLOOR_POINT), classes["ceiling"].color) > 30
    np.testing.assert_array_equal(_pixel(image, info, (11.0, 7.0)), [255, 255, 255])


def test_overlay_is_drawn(bev: tuple[np.ndarray, object]) -> None:
    image, info = bev
    color = _pixel(image, info, (8.5, 7.0))
    assert color[2] > 200 and color[0] < 60 and color[1] < 60


def test_raster_labels_and_object_colours(tiny_scene: Scene) -> None:
    raster = raster_bev(tiny_scene, meters_per_pixel=0.05)
    names = raster.class_names
    for point, expected in ((FLOOR_POINT, "floor"), (WALL_POINT, "wall"), (ROAD_POINT, "road")):
        row, col = raster.info.world_to_raster(point)
        assert names[raster.class_index[row, col]] == expected
    for object_id, category, center, _size, _yaw in OBJECTS:
        row, col = raster.info.world_to_raster(center[:2])
        assert raster.instance_id[row, col] == object_id
        assert raster.class_index[row, col] == -1
        assert raster.height[row, col] == pytest.approx(center[2] * 2, abs=1e-4)  # top of the box
        expected = lighten(default_color(category), 0.35)
        assert _distance(raster.rgb[row, col].astype(int), expected) < 6
    # The table (1.2 x 0.8, yaw 2.5) is rotated counter-clockwise: 0.55 m along its long axis is
    # on it, 0.55 m along the axis of yaw -2.5 is not.
    on_table = raster.info.world_to_raster(np.array([7.0, 5.0]) + 0.55 * np.array([np.cos(2.5), np.sin(2.5)]))
    beside = raster.info.world_to_raster(np.array([7.0, 5.0]) + 0.55 * np.array([np.cos(-2.5), np.sin(-2.5)]))
    assert raster.instance_id[tuple(on_table)] == 3
    assert raster.instance_id[tuple(beside)] == 0


def test_wall_edges_are_shaded(tiny_scene: Scene) -> None:
    raster = raster_bev(tiny_scene, meters_per_pixel=0.02)
    wall = np.array(tiny_scene.annotations.terrain_classes["wall"].color)
    row_in, col = raster.info.world_to_raster(WALL_POINT)
    row_edge, _ = raster.info.world_to_raster((5.0, 0.29))
    assert (raster.rgb[row_edge, col] < raster.rgb[row_in, col]).all()
    np.testing.assert_array_equal(raster.rgb[row_in, col], wall)


def test_resolution_choice() -> None:
    assert auto_meters_per_pixel(3200.0) == pytest.approx(2.0)
    assert auto_meters_per_pixel(5.0) == pytest.approx(0.01)


def test_too_fine_resolution_is_rejected(tiny_scene: Scene, tmp_path: Path) -> None:
    with pytest.raises(SceneError, match="use at least"):
        render_bev(tiny_scene, tmp_path / "bev.png", meters_per_pixel=0.001)


def test_hillshade_brightens_slopes_facing_the_light() -> None:
    # Light comes from -x/+y. Ramp "west" faces -x (towards the light), ramp "east" faces +x.
    def ramp(x0: float, z0: float, z1: float) -> MeshData:
        vertices = np.array([[x0, 0, z0], [x0 + 2, 0, z1], [x0 + 2, 2, z1], [x0, 2, z0]], dtype=float)
        return MeshData(vertices, np.array([[0, 1, 2], [0, 2, 3]]))

    surfaces = (
        Surface("flat", "ground", ramp(0.0, 0.0, 0.0)),
        Surface("west", "ground", ramp(2.0, 0.0, 0.5)),  # rises towards +x: its normal tilts to -x
        Surface("east", "ground", ramp(4.0, 0.5, 0.0)),
    )
    scene = scene_of(surfaces, scene_id="ramps", scene_type="outdoor")  # bounds x 0..6, y 0..2
    raster = raster_bev(scene, meters_per_pixel=0.25)  # 6 cm rise per pixel
    flat, west, east = (
        raster.rgb[tuple(raster.info.world_to_raster((x, 1.0)))].astype(int) for x in (1.0, 3.0, 5.0)
    )
    ground = np.array(scene.annotations.terrain_classes["ground"].color)
    np.testing.assert_array_equal(flat, ground)
    assert (west > flat).all()
    assert (east < flat).all()
    # Inside a ramp the colour is the plain hillshade: a steady slope is not outlined as a step.
    light = np.array([-1.0, 1.0, 1.5]) / np.linalg.norm([-1.0, 1.0, 1.5])
    normal = np.array([-0.25, 0.0, 1.0]) / np.linalg.norm([-0.25, 0.0, 1.0])
    np.testing.assert_allclose(west, ground * (normal @ light) / light[2], atol=1.0)


def test_filled_polygons_are_tinted_without_seams(tiny_scene: Scene, tmp_path: Path) -> None:
    # Two squares sharing the edge x = 8 cover the floor point; red at half opacity.
    left = np.array([[7.0, 1.5], [8.0, 1.5], [8.0, 2.5], [7.0, 2.5]])
    right = np.array([[8.0, 1.5], [9.0, 1.5], [9.0, 2.5], [8.0, 2.5]])
    overlay = BevOverlay("area", polygons=[left, right], color=(1.0, 0.0, 0.0), fill_alpha=0.5)
    path = tmp_path / "filled.png"
    info = render_bev(tiny_scene, path, meters_per_pixel=MPP, overlays=[overlay])
    image = np.asarray(Image.open(path).convert("RGB"))
    floor = np.array(tiny_scene.annotations.terrain_classes["floor"].color)
    expected = 0.5 * floor + 0.5 * np.array([255, 0, 0])
    inside = _pixel(image, info, (7.5, 2.0))
    assert _distance(inside, tuple(expected)) < 8, inside
    on_shared_edge = _pixel(image, info, (8.0 + MPP / 2, 2.0))
    assert _distance(on_shared_edge, tuple(inside)) < 3, (on_shared_edge, inside)
    assert _distance(_pixel(image, info, (6.5, 2.0)), tuple(floor)) < 8  # outside: untouched


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"polygons": [np.zeros((2, 2))]}, "N >= 3"),
        ({"polygons": [np.zeros((4, 3))]}, "N >= 3"),
        ({"segments": np.zeros((3, 2))}, r"\(K, 2, 2\)"),
        ({"fill_alpha": 1.5}, "fill_alpha"),
    ],
)
def test_overlay_shapes_are_checked(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        BevOverlay("bad", **kwargs)


def _assert_same_raster(a: BevRaster, b: BevRaster) -> None:
    assert a.info == b.info and a.class_names == b.class_names
    for name in ("rgb", "class_index", "instance_id", "height"):
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype, name
        np.testing.assert_array_equal(x, y, err_msg=name)  # NaN equals NaN here


@pytest.mark.parametrize("rays_per_band", [1, 281, 561, 839, 7000])
def test_bands_give_the_raster_of_one_band(tiny_scene: Scene, rays_per_band: int) -> None:
    # 240 x 280 pixels: bands of 1, 1, 2, 2 and 25 rows (the last band shorter)
    whole = raster_bev(tiny_scene, meters_per_pixel=0.05, rays_per_band=10**9)
    _assert_same_raster(raster_bev(tiny_scene, meters_per_pixel=0.05, rays_per_band=rays_per_band), whole)


def test_a_banded_png_has_the_bytes_of_a_one_band_png(tiny_scene: Scene, tmp_path: Path) -> None:
    overlay = BevOverlay("path", np.array([[[1.0, 7.0], [9.5, 7.0]]]), color=(0.0, 0.0, 1.0))
    for name, rays_per_band in (("banded.png", 1000), ("whole.png", 10**9)):
        render_bev(
            tiny_scene, tmp_path / name, meters_per_pixel=MPP, overlays=[overlay], rays_per_band=rays_per_band
        )
    assert (tmp_path / "banded.png").read_bytes() == (tmp_path / "whole.png").read_bytes()


@pytest.mark.parametrize("patches", [1, 2, 3])
def test_bands_with_a_single_hit_give_the_raster_of_one_band(patches: int) -> None:
    # Small tilted patches, each covering one pixel centre (0.25 m pixels) in a row of its own,
    # under a ceiling the BEV does not show: bands of one row hold one hit each.
    def patch(x: float, y: float, rise: float) -> MeshData:
        x0, y0, x1, y1 = x - 0.08, y - 0.08, x + 0.08, y + 0.08
        vertices = np.array([[x0, y0, 0.0], [x1, y0, rise], [x1, y1, rise + 0.03], [x0, y1, 0.03]])
        return MeshData(vertices, np.array([[0, 1, 2], [0, 2, 3]]))

    spots = ((0.125, 0.125, 0.07), (1.375, 0.875, 0.11), (1.875, 1.625, 0.05))[:patches]
    surfaces = [Surface(f"patch_{i}", "ground", patch(x, y, rise)) for i, (x, y, rise) in enumerate(spots)]
    surfaces.append(Surface("ceiling", "ceiling", quad(0.0, 0.0, 2.0, 2.0, 3.0)))
    scene = scene_of(surfaces, scene_id="patches", scene_type="outdoor")
    whole = raster_bev(scene, meters_per_pixel=0.25, rays_per_band=10**9)
    assert np.isfinite(whole.height).sum() == patches
    for rays_per_band in (1, 16, 24):  # bands of 1, 2 and 3 rows
        _assert_same_raster(raster_bev(scene, meters_per_pixel=0.25, rays_per_band=rays_per_band), whole)


def test_rays_per_band_must_be_positive(tiny_scene: Scene) -> None:
    with pytest.raises(ValueError, match="rays_per_band"):
        raster_bev(tiny_scene, meters_per_pixel=0.05, rays_per_band=0)
