"""The lit look on known geometry: Lambert's cosine law, shadows, crossing markings where the map has them."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from navverse.city.geometry.scene import CityGeometry, city_scene
from navverse.city.map import CityMap
from navverse.city.osm.reader import read_osm
from navverse.look.materials import MATERIAL_NAMES
from navverse.look.scene_look import map_details, scene_look
from navverse.look.settings import LookSettings
from navverse.look.sky import sun_sky
from navverse.scene.geometry import Scene, Surface
from navverse.sim.camera import CameraIntrinsics, look_at
from navverse.sim.render import FLAT_COLOR, NOTHING_HIT, SceneRenderer, Shading
from tests.scenes import box_part, quad, scene_of

SMALL = CameraIntrinsics.from_hfov(160, 120, 90.0)
NOON = LookSettings(time_of_day=12.0, day_of_year=80, latitude_deg=45.0)  # the sun due south, 45 deg up
GREY = (180, 180, 180)
T_JUNCTION = Path(__file__).parents[1] / "city" / "data" / "t_junction.osm"


def _pixel(pose: np.ndarray, intrinsics: CameraIntrinsics, point: np.ndarray) -> tuple[int, int]:
    """(row, col) of the pixel a world point projects to."""
    local = np.linalg.inv(pose) @ np.append(point, 1.0)
    u, v = intrinsics.project(local[:3])
    return math.floor(v), math.floor(u)


def _seen(renderer: SceneRenderer, point: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """The light falling on a surface point seen head-on from 4 m in front of it."""
    eye = point + 4.0 * normal
    pose = look_at(eye, point)
    row, col = _pixel(pose, renderer.intrinsics, point)
    return renderer.radiance(pose, component="light")[row, col]


def test_a_face_turned_from_the_sun_is_darker_by_lamberts_ratio() -> None:
    # Three grey panels, their faces vertical (the same sky light): A faces the sun's azimuth, B is turned
    # 60 degrees from it, C faces away (sky light only).
    faces = {"A": 0.0, "B": math.radians(60.0), "C": math.pi}
    objects = [
        box_part("panel", (6.0 * k, 0.0, 1.0), (1.0, 0.2, 1.0), yaw, rgb=GREY)
        for k, yaw in enumerate(faces.values())
    ]
    scene = scene_of(
        [Surface("floor", "floor", quad(-5.0, -5.0, 20.0, 5.0, 0.0))], objects, scene_id="panels"
    )
    renderer = SceneRenderer(scene, intrinsics=SMALL, look=NOON)
    sun = sun_sky(NOON).sun_direction
    seen, cosines = {}, {}
    for k, (name, yaw) in enumerate(faces.items()):
        normal = np.array([math.sin(yaw), -math.cos(yaw), 0.0])  # the panel's -y face, turned by its yaw
        seen[name] = _seen(renderer, np.array([6.0 * k, 0.0, 1.0]) + 0.1 * normal, normal)
        cosines[name] = float(normal @ sun)
    assert cosines["A"] > 0.6 and cosines["C"] < 0.0
    direct_a, direct_b = seen["A"] - seen["C"], seen["B"] - seen["C"]
    assert (seen["B"] < seen["A"]).all()
    pose = look_at(np.array([0.0, -4.0, 1.0]), np.array([0.0, 0.0, 1.0]))
    parts = {c: renderer.radiance(pose, component=c) for c in ("radiance", "albedo", "light")}
    np.testing.assert_allclose(parts["radiance"], parts["albedo"] * parts["light"], rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(direct_b / direct_a, cosines["B"] / cosines["A"], rtol=0.02)


def test_a_point_behind_an_occluder_is_in_shadow() -> None:
    # A 2 m wall along x on a grey ground; the noon sun in the south throws its shadow 2 m to the north.
    objects = [
        box_part("ground", (0.0, 0.0, -0.05), (40.0, 40.0, 0.1), rgb=GREY),
        box_part("wall", (0.0, 0.0, 1.0), (6.0, 0.2, 2.0), rgb=GREY),
    ]
    scene = scene_of([Surface("far", "floor", quad(-1.0, -1.0, 1.0, 1.0, -30.0))], objects, scene_id="shadow")
    renderer = SceneRenderer(scene, intrinsics=SMALL, look=NOON)
    sky = sun_sky(NOON)
    pose = look_at(np.array([4.0, 1.5, 9.0]), np.array([0.0, 1.5, 0.0]))
    image = renderer.radiance(pose, component="light")  # the ground's grain aside
    shaded = image[_pixel(pose, SMALL, np.array([0.0, 1.0, 0.0]))]
    lit = image[_pixel(pose, SMALL, np.array([0.0, 4.0, 0.0]))]
    south = image[_pixel(pose, SMALL, np.array([0.0, -3.0, 0.0]))]
    np.testing.assert_allclose(lit, south, rtol=1e-4)
    # In the shadow only the sky lights the ground; in the open the sun adds its cosine.
    expected = sky.sky_light / (sky.sky_light + sky.sun_color * sky.sun_direction[2])
    np.testing.assert_allclose(shaded / lit, expected, rtol=0.02)
    without = SceneRenderer(scene, intrinsics=SMALL, look=NOON.model_copy(update={"shadows": False}))
    np.testing.assert_allclose(
        without.radiance(pose, component="light")[_pixel(pose, SMALL, np.array([0.0, 1.0, 0.0]))],
        lit,
        rtol=1e-4,
    )


@pytest.fixture(scope="module")
def junction() -> tuple[Scene, object]:
    city = read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))
    return city_scene(city, scene_id="t-junction", geometry=CityGeometry(junction_crosswalks=False)), city


def test_the_mapped_zebra_crossing_shows_its_stripes_there(junction: tuple[Scene, object]) -> None:
    # The map's crossing is at x = -20 on the main street (along x, 7 m wide): stripes along the street
    # direction, 0.5 m wide and 0.5 m apart, across the whole carriageway; none on the road beside it.
    scene, city = junction
    look = scene_look(scene, LookSettings(), details=map_details(scene, city))
    intrinsics = CameraIntrinsics.from_hfov(320, 240, 90.0)
    renderer = SceneRenderer(scene, intrinsics=intrinsics, look=look)
    pose = look_at(np.array([-20.0, 0.0, 12.0]), np.array([-20.0, 0.0, 0.0]), up=(0.0, 1.0, 0.0))
    frame = renderer.render(pose)
    crosswalk = frame.terrain == renderer.class_names.index("crosswalk")
    rows, cols = np.nonzero(crosswalk)
    # Pixel -> world on the ground: 12 m below a camera looking straight down (y up the image).
    metres = 12.0 / intrinsics.fx
    xs = -20.0 + (cols + 0.5 - intrinsics.cx) * metres
    ys = -(rows + 0.5 - intrinsics.cy) * metres
    assert abs(xs.mean() + 20.0) < 0.5 and ys.max() - ys.min() > 6.0  # at the mapped place, road-wide
    luma = frame.rgb.astype(float) @ np.array([0.2126, 0.7152, 0.0722])
    bright = luma[rows, cols] > 170.0
    assert 0.35 < bright.mean() < 0.65

    # Along the crossing the stripes alternate with a 1 m period: brightness in phase with a square wave
    # of 0.5 m stripes and gaps (at its best phase), and not with one of another period.
    def agreement(period: float) -> float:
        return max(
            float((bright == (np.mod(ys - phase, period) < period / 2)).mean())
            for phase in np.linspace(0.0, period, 40, endpoint=False)
        )

    assert agreement(1.0) > 0.9 and agreement(1.4) < 0.75
    beside = (np.abs(xs + 20.0) < 1.0) & ~crosswalk[rows, cols]
    assert not beside.any()
    road = frame.terrain == renderer.class_names.index("road")
    road_rows, road_cols = np.nonzero(road)
    road_x = -20.0 + (road_cols + 0.5 - intrinsics.cx) * metres
    road_y = -(road_rows + 0.5 - intrinsics.cy) * metres
    off_lines = (np.abs(road_x + 20.0) > 3.0) & (np.abs(road_y) > 0.3) & (np.abs(road_y) < 3.0)
    assert (luma[road_rows[off_lines], road_cols[off_lines]] < 150.0).all()


def _crosswalk_seen(
    junction: tuple[Scene, CityMap], markings: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The T-junction's crossing mapped with other `markings`, seen from 12 m straight above: per crosswalk
    pixel its world x and y, whether it shows paint, and its luma."""
    scene, city = junction
    crossings = [c.model_copy(update={"markings": markings}) for c in city.crossings]
    marked = CityMap.model_validate(
        city.model_copy(update={"crossings": crossings}).model_dump(by_alias=True)
    )
    look = scene_look(scene, LookSettings(), details=map_details(scene, marked))
    intrinsics = CameraIntrinsics.from_hfov(320, 240, 90.0)
    renderer = SceneRenderer(scene, intrinsics=intrinsics, look=look)
    pose = look_at(np.array([-20.0, 0.0, 12.0]), np.array([-20.0, 0.0, 0.0]), up=(0.0, 1.0, 0.0))
    frame, materials = renderer.render(pose), renderer.materials(pose)
    rows, cols = np.nonzero(frame.terrain == renderer.class_names.index("crosswalk"))
    metres = 12.0 / intrinsics.fx
    xs = -20.0 + (cols + 0.5 - intrinsics.cx) * metres
    ys = -(rows + 0.5 - intrinsics.cy) * metres
    painted = materials[rows, cols] == MATERIAL_NAMES.index("marking")
    luma = frame.rgb[rows, cols].astype(float) @ np.array([0.2126, 0.7152, 0.0722])
    return xs, ys, painted, luma


def test_a_crossing_mapped_with_lines_shows_them_along_its_edges(junction: tuple[Scene, CityMap]) -> None:
    # The crosswalk spans x = -22 .. -18 (4 m along the street) and the carriageway in y: 0.25 m lines
    # along its two long edges, across the whole street, and no bars between them.
    xs, ys, painted, luma = _crosswalk_seen(junction, "lines")
    from_edge = np.minimum(xs - xs.min(), xs.max() - xs)
    assert xs.max() - xs.min() == pytest.approx(4.0, abs=0.3)
    assert painted[from_edge < 0.12].mean() > 0.95 and np.median(luma[from_edge < 0.12]) > 170.0
    assert not painted[from_edge > 0.4].any()
    for side in (xs < -20.0, xs > -20.0):
        assert np.ptp(ys[painted & side]) > 6.0


def test_a_crossing_mapped_unpainted_shows_no_marking(junction: tuple[Scene, CityMap]) -> None:
    xs, _, painted, luma = _crosswalk_seen(junction, "none")
    assert len(xs) > 1000 and not painted.any() and (luma < 150.0).mean() > 0.95


def test_flat_images_are_a_shading_and_lit_ones_a_look() -> None:
    scene = scene_of([Surface("floor", "floor", quad(-1.0, -1.0, 1.0, 1.0, 0.0))], [], scene_id="flat")
    with pytest.raises(ValueError, match="not both"):
        SceneRenderer(scene, shading=Shading(), look=LookSettings())
    flat = SceneRenderer(scene, intrinsics=SMALL, shading=Shading())
    assert flat.look is None
    with pytest.raises(ValueError, match="radiance"):
        flat.radiance(look_at(np.array([0.0, 0.0, 2.0]), np.zeros(3), up=(0.0, 1.0, 0.0)))


def test_the_material_image_names_what_each_lit_pixel_shows(junction: tuple[Scene, object]) -> None:
    scene, city = junction
    renderer = SceneRenderer(
        scene, intrinsics=SMALL, look=scene_look(scene, LookSettings(), details=map_details(scene, city))
    )
    pose = look_at(
        np.array([-20.0, -6.0, 1.6]), np.array([-20.0, 30.0, 1.0])
    )  # across the crossing, sky above
    materials, frame = renderer.materials(pose), renderer.render(pose)
    assert ((materials == NOTHING_HIT) == (frame.depth == 0.0)).all() and (materials == NOTHING_HIT).any()
    assert not (materials == FLAT_COLOR).any()  # every surface hit shows a material
    crosswalk = materials[frame.terrain == renderer.class_names.index("crosswalk")]
    assert MATERIAL_NAMES.index("marking") in crosswalk and len(set(crosswalk.tolist())) >= 2  # stripes, gaps
    flat = SceneRenderer(scene, intrinsics=SMALL, shading=Shading())
    with pytest.raises(ValueError, match="materials"):
        flat.materials(pose)


def test_lit_frames_do_not_depend_on_how_the_work_is_split(junction: tuple[Scene, object]) -> None:
    scene, city = junction
    look = scene_look(scene, LookSettings(), details=map_details(scene, city))
    pose = look_at(np.array([-20.0, -6.0, 1.6]), np.array([-20.0, 30.0, 1.0]))
    frames = [SceneRenderer(scene, look=look, threads=threads).render(pose) for threads in (1, 2, 3)]
    for frame in frames[1:]:
        assert np.array_equal(frame.rgb, frames[0].rgb) and np.array_equal(frame.depth, frames[0].depth)
