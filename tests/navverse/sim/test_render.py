"""The ray-cast camera on known geometry: depths, labels, colours, projection, misses, determinism."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navverse.scene.compose import transform_scene
from navverse.scene.geometry import MeshData, Scene, Surface, yaw_matrix
from navverse.sim.camera import CameraIntrinsics, look_at, optical_from_body, optical_pose
from navverse.sim.render import Frame, SceneRenderer, Shading
from tests.scenes import box_part, quad, scene_of

EYE = np.array([0.0, 0.0, 1.0])
WALL_X = 4.0  # the wall's face towards the camera
OBJECT_ID = 2  # the red box; object 1 is a cabinet behind the wall, out of every view
OBJECT_CENTER = (2.0, 0.6, 0.5)
OBJECT_SIZE = (0.4, 0.4, 1.0)
OBJECT_RGB = (200, 40, 40)
CEILING_Z = 3.0
SMALL = CameraIntrinsics.from_hfov(160, 120, 90.0)
FLAT = Shading(ambient=1.0, key=0.0, fill=0.0, headlight=0.0, fog=0.0, edge_shade=1.0, terrain_lighten=0.0)


def build_scene(offset: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Scene:
    """A floor, a wall across +x at 4 m, a ceiling at 3 m and one red box (id 2) in between, all
    shifted by `offset`. A cabinet (id 1) stands behind the wall, hidden from every camera here, so
    that the box's id is not the first one."""
    objects = [
        box_part("cabinet", (5.0, 0.0, 0.2), (0.4, 0.4, 0.4), rgb=(30, 160, 60)),
        box_part("chair", OBJECT_CENTER, OBJECT_SIZE, rgb=OBJECT_RGB),
    ]
    surfaces = (
        Surface("floor", "floor", quad(-1.0, -3.0, 6.0, 3.0, 0.0)),
        Surface("wall", "wall", MeshData.box((0.2, 6.0, CEILING_Z), center=(WALL_X + 0.1, 0.0, 1.5))),
        Surface("ceiling", "ceiling", quad(-1.0, -3.0, 6.0, 3.0, CEILING_Z)),
    )
    return transform_scene(scene_of(surfaces, objects, scene_id="render_box"), translation=offset)


@pytest.fixture(scope="module")
def scene() -> Scene:
    """The test scene at the world origin."""
    return build_scene()


@pytest.fixture(scope="module")
def flat(scene: Scene) -> SceneRenderer:
    """Unshaded renderer: every pixel shows its face colour exactly."""
    return SceneRenderer(scene, intrinsics=SMALL, shading=FLAT)


@pytest.fixture(scope="module")
def ahead(flat: SceneRenderer) -> Frame:
    """Camera at 1 m height looking along +x at the wall."""
    return flat.render(look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0))))


def _pixel_of(
    pose: np.ndarray, intrinsics: CameraIntrinsics, point: np.ndarray
) -> tuple[tuple[int, int], float]:
    """(row, col) of the pixel a world point projects to, and the point's z-depth."""
    local = np.linalg.inv(pose) @ np.append(point, 1.0)
    u, v = intrinsics.project(local[:3])
    return (math.floor(v), math.floor(u)), float(local[2])


def test_intrinsics_from_hfov() -> None:
    k = CameraIntrinsics.from_hfov(640, 480, 90.0)
    np.testing.assert_allclose(k.matrix(), [[320.0, 0.0, 320.0], [0.0, 320.0, 240.0], [0.0, 0.0, 1.0]])
    assert k.hfov_deg == pytest.approx(90.0)
    assert k.vfov_deg == pytest.approx(2 * math.degrees(math.atan(240 / 320)))
    with pytest.raises(ValueError, match="hfov_deg"):
        CameraIntrinsics.from_hfov(640, 480, 180.0)
    with pytest.raises(ValueError, match="width"):
        CameraIntrinsics(width=0, height=480, fx=1.0, fy=1.0, cx=0.0, cy=0.0)


def test_look_at_agrees_with_the_body_convention() -> None:
    yaw = 0.7
    body = np.eye(4)
    body[:3, :3] = yaw_matrix(yaw)
    body[:3, 3] = EYE
    forward = np.array([math.cos(yaw), math.sin(yaw), 0.0])
    np.testing.assert_allclose(optical_pose(body), look_at(EYE, EYE + forward), atol=1e-12)
    # Body x (forward) is optical z, body y (left) is optical -x, body z (up) is optical -y.
    np.testing.assert_allclose(optical_from_body() @ [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    np.testing.assert_allclose(optical_from_body() @ [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0])
    np.testing.assert_allclose(optical_from_body() @ [0.0, 0.0, 1.0], [0.0, -1.0, 0.0])


def test_frame_shapes_and_types(ahead: Frame) -> None:
    assert ahead.rgb.shape == (120, 160, 3) and ahead.rgb.dtype == np.uint8
    assert ahead.depth.shape == (120, 160) and ahead.depth.dtype == np.float32
    assert ahead.semantic.shape == (120, 160) and ahead.semantic.dtype == np.int32
    assert ahead.terrain.shape == (120, 160) and ahead.terrain.dtype == np.int16


def test_depth_is_the_analytic_z_distance(ahead: Frame) -> None:
    assert ahead.depth[60, 80] == pytest.approx(WALL_X - EYE[0], abs=0.01)
    # Z-depth, not ray length: a wall perpendicular to the optical axis has one depth everywhere,
    # also at a pixel whose ray is ~35 degrees off the axis.
    wall = ahead.terrain == 1
    assert wall[60, 25]
    np.testing.assert_allclose(ahead.depth[wall], WALL_X, atol=0.01)


def test_labels_of_object_wall_and_floor(flat: SceneRenderer, ahead: Frame) -> None:
    assert flat.class_names == ("floor", "wall", "ceiling")
    (row, col), z = _pixel_of(look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0))), SMALL, np.array([1.8, 0.6, 0.5]))
    assert ahead.semantic[row, col] == OBJECT_ID
    assert ahead.terrain[row, col] == -1
    assert ahead.depth[row, col] == pytest.approx(z, abs=0.01)
    assert ahead.semantic[60, 80] == 0 and ahead.terrain[60, 80] == 1  # the wall
    assert ahead.semantic[115, 80] == 0 and ahead.terrain[115, 80] == 0  # the floor
    assert ahead.semantic[2, 80] == 0 and ahead.terrain[2, 80] == 2  # the ceiling
    assert set(np.unique(ahead.semantic)) == {0, OBJECT_ID}


def test_unshaded_colours_are_the_face_and_class_colours(scene: Scene, ahead: Frame) -> None:
    object_pixels = ahead.rgb[ahead.semantic == OBJECT_ID]
    assert len(object_pixels) > 50
    assert (object_pixels == OBJECT_RGB).all()
    classes = scene.annotations.terrain_classes
    assert (ahead.rgb[ahead.terrain == 1] == classes["wall"].color).all()
    assert (ahead.rgb[ahead.terrain == 0] == classes["floor"].color).all()


def test_shaded_colour_follows_the_lighting_formula(scene: Scene) -> None:
    # Headlight only: the box's front face (normal -x, facing the camera) gets cos(ray, normal).
    shading = Shading(ambient=0.2, key=0.0, fill=0.0, headlight=0.8, fog=0.0, edge_shade=1.0)
    renderer = SceneRenderer(scene, intrinsics=SMALL, shading=shading)
    pose = look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0)))
    point = np.array([OBJECT_CENTER[0] - 0.2, OBJECT_CENTER[1], 0.5])
    (row, col), _ = _pixel_of(pose, SMALL, point)
    frame = renderer.render(pose)
    assert frame.semantic[row, col] == OBJECT_ID
    ray = np.array([(col + 0.5 - SMALL.cx) / SMALL.fx, (row + 0.5 - SMALL.cy) / SMALL.fy, 1.0])
    cosine = 1.0 / np.linalg.norm(ray)  # normal is -z in the optical frame
    expected = np.array(OBJECT_RGB) * (0.2 + 0.8 * cosine)
    np.testing.assert_allclose(frame.rgb[row, col], expected, atol=1.0)
    # The default, lit look keeps the hue (red well above green and blue, which the sky's bluish light
    # moves a little) and a recognisable brightness.
    default = SceneRenderer(scene, intrinsics=SMALL).render(pose)
    shaded = default.rgb[row, col].astype(float)
    ratio = shaded / np.array(OBJECT_RGB)
    assert 0.5 < ratio[0] < 1.3
    assert shaded[0] > 3 * max(shaded[1], shaded[2]) and abs(shaded[1] - shaded[2]) < 8


def test_projection_agrees_with_the_rays(scene: Scene) -> None:
    # An oblique camera: points on the box's visible faces project to pixels that see the box, at the
    # z-depth where that pixel's ray meets the face's plane. Full resolution keeps pixel centres on
    # the point's face (the top is seen at a grazing angle).
    intrinsics = CameraIntrinsics.from_hfov(640, 480, 90.0)
    eye = np.array([-0.5, -1.5, 1.6])
    pose = look_at(eye, np.array(OBJECT_CENTER))
    frame = SceneRenderer(scene, intrinsics=intrinsics, shading=FLAT).render(pose)
    center = np.array(OBJECT_CENTER)
    half = np.array(OBJECT_SIZE) / 2
    rng = np.random.default_rng(3)
    for _ in range(60):
        axis, sign = [(0, -1.0), (1, -1.0), (2, 1.0)][rng.integers(3)]  # the -x, -y and top faces
        normal = np.zeros(3)
        normal[axis] = sign
        point = center + rng.uniform(-0.7, 0.7, size=3) * half
        point[axis] = center[axis] + sign * half[axis]
        (row, col), _ = _pixel_of(pose, intrinsics, point)
        assert frame.semantic[row, col] == OBJECT_ID
        k = intrinsics
        ray = pose[:3, :3] @ [(col + 0.5 - k.cx) / k.fx, (row + 0.5 - k.cy) / k.fy, 1.0]
        expected = normal @ (point - eye) / (normal @ ray)  # ray parameter = z-depth (optical z = 1)
        assert frame.depth[row, col] == pytest.approx(expected, abs=0.005)


def test_misses_have_zero_depth_and_background(scene: Scene) -> None:
    renderer = SceneRenderer(scene, intrinsics=SMALL)
    above = np.array([2.0, 0.0, 10.0])
    sky = renderer.render(look_at(above, np.add(above, (0.0, 0.0, 1.0)), up=(1.0, 0.0, 0.0)))
    assert not sky.hit.any()
    assert (sky.depth == 0.0).all()
    assert (sky.rgb == renderer.shading.background).all()
    assert (sky.semantic == 0).all() and (sky.terrain == -1).all()
    # From outside, looking away from the scene: nothing; looking back at it: the room's outside.
    outside = np.array([-5.0, 0.0, 1.0])
    away = renderer.render(look_at(outside, np.add(outside, (-1.0, 0.0, 0.0))))
    assert not away.hit.any()
    back = renderer.render(look_at(outside, np.add(outside, (1.0, 0.0, 0.0))))
    assert back.hit.any() and not back.hit.all()
    assert (back.rgb[~back.hit] == renderer.shading.background).all()


def test_depth_range_clips_far_and_near(scene: Scene) -> None:
    pose = look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0)))
    far = SceneRenderer(scene, intrinsics=SMALL, depth_range=(0.1, 3.0), shading=FLAT).render(pose)
    assert far.depth[60, 80] == 0.0 and far.terrain[60, 80] == -1
    assert (far.rgb[60, 80] == FLAT.background).all()
    assert far.depth.max() <= 3.0
    # A near plane beyond the box removes it: the wall shows through.
    (row, col), _ = _pixel_of(pose, SMALL, np.array([1.8, 0.6, 0.9]))
    near = SceneRenderer(scene, intrinsics=SMALL, depth_range=(2.5, 100.0)).render(pose)
    assert near.semantic[row, col] == 0 and near.terrain[row, col] == 1
    assert near.depth[row, col] > 2.5


def test_hidden_classes_are_left_out(scene: Scene) -> None:
    renderer = SceneRenderer(scene, intrinsics=SMALL, hidden_classes=("wall", "no_such_class"))
    frame = renderer.render(look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0))))
    assert not (frame.terrain == 1).any()
    assert frame.depth[60, 80] == 0.0  # past the wall's place there is nothing
    assert renderer.class_names == ("floor", "wall", "ceiling")  # indices stay the scene's
    one = SceneRenderer(scene, intrinsics=SMALL, hidden_classes="wall")  # a single name is one class
    assert (one.render(look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0)))).depth == frame.depth).all()


def test_far_from_the_world_origin(flat: SceneRenderer, ahead: Frame) -> None:
    # 100 km out, float32 world coordinates would be off by centimetres; the local frame keeps mm.
    offset = np.array([1.0e5, -2.0e5, 30.0])
    renderer = SceneRenderer(build_scene(tuple(offset)), intrinsics=SMALL, shading=FLAT)
    frame = renderer.render(look_at(EYE + offset, EYE + offset + np.array([1.0, 0.0, 0.0])))
    assert frame.depth[60, 80] == pytest.approx(WALL_X, abs=0.002)
    assert (frame.semantic == ahead.semantic).mean() > 0.999
    np.testing.assert_allclose(frame.depth, ahead.depth, atol=0.005)


def test_rendering_is_deterministic(scene: Scene) -> None:
    poses = [look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0))), look_at((-0.5, -1.5, 1.6), OBJECT_CENTER)]
    first = SceneRenderer(scene, intrinsics=SMALL).render_batch(poses)
    second = SceneRenderer(scene, intrinsics=SMALL)
    again = [second.render(p) for p in poses] + [second.render(poses[0])]
    for a, b in zip([*first, first[0]], again, strict=True):
        for name in ("rgb", "depth", "semantic", "terrain"):
            assert getattr(a, name).tobytes() == getattr(b, name).tobytes()


def test_frames_are_independent_of_later_renders(flat: SceneRenderer) -> None:
    frame = flat.render(look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0))))
    copy = frame.depth.copy(), frame.rgb.copy()
    flat.render(look_at(EYE, np.add(EYE, (0.0, 1.0, 0.0))))
    assert (frame.depth == copy[0]).all() and (frame.rgb == copy[1]).all()


def test_bad_poses_are_rejected(flat: SceneRenderer) -> None:
    with pytest.raises(ValueError, match="4x4"):
        flat.render(np.eye(3))
    with pytest.raises(ValueError, match="rotation"):
        flat.render(np.diag([2.0, 1.0, 1.0, 1.0]))
    with pytest.raises(ValueError, match="finite"):
        flat.render(np.full((4, 4), np.nan))
    with pytest.raises(ValueError, match="4x4"):
        flat.render_batch([np.eye(4), np.eye(4)[:3]])
    with pytest.raises(ValueError, match="depth_range"):
        SceneRenderer(_floor_only(), depth_range=(0.0, 10.0))


def _floor_only() -> Scene:
    """A floor the camera at `EYE` would see ahead of it, unless the renderer hides it."""
    return scene_of([Surface("floor", "floor", quad(-1.0, -3.0, 6.0, 3.0, 0.0))], scene_id="floor_only")


def test_empty_scene_renders_background() -> None:
    # Its only surface hidden, the renderer has no geometry at all.
    pose = look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0)))
    assert SceneRenderer(_floor_only(), intrinsics=SMALL).render(pose).hit.any()
    renderer = SceneRenderer(_floor_only(), intrinsics=SMALL, hidden_classes=("floor",))
    frame = renderer.render(pose)
    assert not frame.hit.any() and (frame.rgb == renderer.shading.background).all()


def test_default_camera_is_640_by_480(scene: Scene) -> None:
    frame = SceneRenderer(scene).render(look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0))))
    assert frame.rgb.shape == (480, 640, 3)
    assert frame.depth[240, 320] == pytest.approx(WALL_X, abs=0.01)
