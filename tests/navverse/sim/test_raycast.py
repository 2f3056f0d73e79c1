"""The camera's packet ray caster against Open3D's per-ray cast on the same mesh and rays."""

from __future__ import annotations

import numpy as np
import open3d as o3d
import pytest
import trimesh

from navverse.sim.raycast import NO_FACE, TriangleCaster


def _mesh() -> tuple[np.ndarray, np.ndarray]:
    """A floor, a box on it and a sphere: edges, shared vertices, faces seen from both sides."""
    floor = trimesh.creation.box(extents=(20.0, 20.0, 0.2))
    box = trimesh.creation.box(extents=(2.0, 3.0, 2.5))
    box.apply_translation((3.0, -1.0, 1.35))
    ball = trimesh.creation.icosphere(subdivisions=3, radius=1.5)
    ball.apply_translation((-4.0, 2.0, 1.6))
    mesh = trimesh.util.concatenate([floor, box, ball])
    return np.asarray(mesh.vertices, np.float32), np.asarray(mesh.faces, np.uint32)


def _camera_rays(eye: tuple[float, float, float], width: int = 64, height: int = 48) -> np.ndarray:
    """Pinhole rays (H, W, 6) looking along +x and a little down, directions not unit length."""
    x = np.linspace(-1.0, 1.0, width, dtype=np.float32)
    y = np.linspace(-0.75, 0.75, height, dtype=np.float32)
    forward, right, down = np.array([1, 0, -0.3]), np.array([0, -1, 0]), np.array([0, 0, -1])
    dirs = forward + x[None, :, None] * right + y[:, None, None] * down
    origin = np.broadcast_to(np.asarray(eye, np.float32), dirs.shape)
    return np.ascontiguousarray(np.concatenate([origin, dirs], axis=-1), dtype=np.float32)


def _open3d(vertices: np.ndarray, faces: np.ndarray) -> o3d.t.geometry.RaycastingScene:
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(vertices), o3d.core.Tensor(faces))
    return scene


def test_the_hits_are_those_of_a_per_ray_cast() -> None:
    vertices, faces = _mesh()
    rays = _camera_rays((-9.0, 0.3, 1.2))
    ours = TriangleCaster(vertices, faces).cast(rays)
    theirs = _open3d(vertices, faces).cast_rays(o3d.core.Tensor(rays))
    face = theirs["primitive_ids"].numpy()
    assert ours.face.shape == rays.shape[:2] and ours.barycentric.shape == (*rays.shape[:2], 2)
    hit = face != NO_FACE
    assert 0.3 < hit.mean() < 1.0  # the view holds geometry and sky
    agree = ours.face == face
    assert agree.mean() > 0.999  # only a ray exactly on a shared edge may pick the other triangle
    np.testing.assert_allclose(ours.t_hit[hit & agree], theirs["t_hit"].numpy()[hit & agree], rtol=1e-5)
    np.testing.assert_allclose(
        ours.barycentric[hit & agree], theirs["primitive_uvs"].numpy()[hit & agree], atol=1e-4
    )
    assert np.isinf(ours.t_hit[~hit]).all() and (ours.face[~hit] == NO_FACE).all()


def test_occlusion_stops_at_tfar_as_a_per_ray_test_does() -> None:
    vertices, faces = _mesh()
    rays = _camera_rays((-9.0, 0.3, 1.2)).reshape(-1, 6)
    caster, reference = TriangleCaster(vertices, faces), _open3d(vertices, faces)
    for tfar in (np.inf, 5.0, 0.5):
        ours = caster.occluded(rays, tfar=tfar)
        theirs = reference.test_occlusions(o3d.core.Tensor(rays), tfar=tfar).numpy().astype(bool)
        assert ours.dtype == bool and ours.shape == (len(rays),)
        assert (ours != theirs).mean() < 1e-3
    near, far = caster.occluded(rays, tfar=0.5), caster.occluded(rays, tfar=np.inf)
    assert near.sum() < far.sum() and not (near & ~far).any()


def test_results_do_not_depend_on_the_thread_count() -> None:
    vertices, faces = _mesh()
    rays = _camera_rays((-9.0, 0.3, 1.2), width=160, height=120)
    one, two = TriangleCaster(vertices, faces, threads=1), TriangleCaster(vertices, faces, threads=2)
    a, b = one.cast(rays), two.cast(rays)
    for x, y in ((a.t_hit, b.t_hit), (a.face, b.face), (a.barycentric, b.barycentric)):
        assert x.tobytes() == y.tobytes()
    assert one.occluded(rays).tobytes() == two.occluded(rays).tobytes()


def test_a_ray_count_not_a_multiple_of_the_packet_is_cast_whole() -> None:
    vertices, faces = _mesh()
    rays = _camera_rays((-9.0, 0.3, 1.2)).reshape(-1, 6)[:13]
    caster = TriangleCaster(vertices, faces)
    whole = caster.cast(rays)
    for i in range(len(rays)):
        single = caster.cast(rays[i : i + 1])
        assert single.face[0] == whole.face[0 + i] and single.t_hit[0] == whole.t_hit[i]


def test_an_empty_mesh_hits_nothing() -> None:
    caster = TriangleCaster(np.zeros((0, 3)), np.zeros((0, 3), dtype=int))
    rays = _camera_rays((0.0, 0.0, 1.0), width=5, height=3)
    hits = caster.cast(rays)
    assert caster.num_faces == 0
    assert (hits.face == NO_FACE).all() and np.isinf(hits.t_hit).all()
    assert not caster.occluded(rays).any()


@pytest.mark.parametrize(
    ("vertices", "faces", "message"),
    [
        (np.zeros((3, 3)), [[0, 1, 3]], "does not exist"),
        (np.zeros((3, 3)), [[0, 1, -1]], "negative"),
        (np.zeros((3, 2)), [[0, 1, 2]], r"\(N, 3\)"),
        (np.zeros((3, 3)), [0, 1, 2], r"\(M, 3\)"),
    ],
)
def test_a_bad_mesh_is_refused(vertices, faces, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        TriangleCaster(vertices, faces)


def test_rays_of_another_shape_are_refused() -> None:
    vertices, faces = _mesh()
    with pytest.raises(ValueError, match=r"\(\.\.\., 6\)"):
        TriangleCaster(vertices, faces).cast(np.zeros((4, 3), np.float32))


def _pose(x: float, y: float, yaw: float = 0.0) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0, x], [s, c, 0, y], [0, 0, 1, 0], [0, 0, 0, 1]], dtype=float)


def test_instances_of_a_shape_are_hit_where_they_are_placed() -> None:
    vertices, faces = _mesh()
    caster = TriangleCaster(vertices, faces)
    pillar = trimesh.creation.box(extents=(0.5, 0.5, 1.8))
    pillar.apply_translation((0.0, 0.0, 1.0))  # standing on the floor at its origin
    shape = caster.add_shape(pillar.vertices, pillar.faces)
    rays = _camera_rays((-9.0, 0.3, 1.2))
    before = caster.cast(rays)
    assert (before.instance == -1).all()

    caster.set_instances([shape, shape], [_pose(-6.0, 0.3), _pose(-6.0, -1.5, 0.7)])
    assert caster.num_instances == 2
    hits = caster.cast(rays)
    first = hits.instance == 0
    assert first.any() and (hits.instance == 1).any()
    # The first pillar's near face is 6 - 0.25 m ahead along x: t times the ray's x extent.
    np.testing.assert_allclose(hits.t_hit[first] * rays[first][:, 3], 3.0 - 0.25, atol=1e-3)
    assert (hits.face[first] < len(pillar.faces)).all()
    # Where no pillar stands, the static hits are the same as without instances.
    static = hits.instance == -1
    assert (hits.face[static] == before.face[static]).all()

    # A new frame moves them: the old place is free, the new one is hit; shadow rays see them too.
    caster.set_instances([shape], [_pose(-4.0, 3.0)])
    moved = caster.cast(rays)
    assert (moved.instance <= 0).all() and not (moved.instance[first] == 0).all()
    up = np.array([[-6.0, 0.3, 0.5, 0.0, 0.0, 1.0], [-4.0, 3.0, 0.5, 0.0, 0.0, 1.0]], np.float32)
    assert caster.occluded(up).tolist() == [False, True]

    caster.set_instances(np.zeros(0, int), np.zeros((0, 4, 4)))
    assert caster.cast(rays).face.tobytes() == before.face.tobytes()


def test_bad_instances_are_refused() -> None:
    vertices, faces = _mesh()
    caster = TriangleCaster(vertices, faces)
    shape = caster.add_shape(*_mesh())
    with pytest.raises(ValueError, match="names no shape"):
        caster.set_instances([shape + 1], [_pose(0, 0)])
    with pytest.raises(ValueError, match="one 4 x 4 transform"):
        caster.set_instances([shape, shape], [_pose(0, 0)])
