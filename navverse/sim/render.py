"""The robot's camera: RGB, depth, instance and terrain images of a scene, ray-cast on the CPU.

:class:`SceneRenderer` puts every terrain surface (ceilings included: a camera inside a building
sees them) and every object of a :class:`~navverse.scene.geometry.Scene` into one Open3D
``RaycastingScene`` (Embree) once, then casts one ray per pixel per frame through the pixel centres
of a pinhole camera (:class:`~navverse.sim.camera.CameraIntrinsics`). The per-pixel directions are
computed once; a frame only rotates and translates them. Rays are cast in a local frame centred on the
scene, so float32 keeps sub-millimetre precision far from the world origin.

Each hit pixel takes the colour of its face (objects: their per-face colours, or their category colour
when the mesh has none; terrain: the colour of its class, dark ones lifted a little), shaded by
:class:`Shading`: an ambient term, Lambert from a fixed key light and a weaker opposite fill light, a
headlight at the camera, a slight fog towards the background colour with distance, and a darker line
where depth jumps or the label changes (outlines that make furniture stand out against walls of a
similar colour). Everything per pixel is vectorised numpy on preallocated tables; there is no global
state, and rendering is deterministic: the same scene, camera and pose give the same bytes.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import open3d as o3d
from numpy.typing import ArrayLike

from navverse.scene.colors import default_color
from navverse.scene.geometry import Scene
from navverse.sim.camera import CameraIntrinsics, check_pose

__all__ = ["BACKGROUND_CLASS", "BACKGROUND_ID", "DEFAULT_INTRINSICS", "Frame", "SceneRenderer", "Shading"]

BACKGROUND_ID = 0
"""``Frame.semantic`` where no object was hit (terrain or background)."""
BACKGROUND_CLASS = -1
"""``Frame.terrain`` where no terrain surface was hit (an object or the background)."""

DEFAULT_INTRINSICS = CameraIntrinsics.from_hfov()
"""640 x 480 pixels, 90 degrees horizontal field of view, square pixels, centred principal point."""

_LUMA = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)  # Rec. 709 weights


@dataclass(frozen=True, eq=False)
class Frame:
    """One rendered camera image.

    Parameters
    ----------
    rgb : ndarray of uint8, shape (H, W, 3)
        Shaded sRGB colours; the renderer's background colour where nothing was hit.
    depth : ndarray of float32, shape (H, W)
        Z-depth in meters: the distance along the optical axis (not along the ray) to the hit point.
        ``0.0`` where nothing was hit within the renderer's ``depth_range``: the background, and
        geometry farther than the far limit. Geometry nearer than the near limit is clipped away
        (rays start on the near plane), so what lies behind it is seen, as with a GPU near plane.
    semantic : ndarray of int32, shape (H, W)
        Object instance id (``ObjectAnnotation.id``); ``0`` on terrain and background.
    terrain : ndarray of int16, shape (H, W)
        Index of the hit terrain class in ``SceneRenderer.class_names`` (the scene's terrain class
        order); ``-1`` on objects and background.
    """

    rgb: np.ndarray
    depth: np.ndarray
    semantic: np.ndarray
    terrain: np.ndarray

    @property
    def hit(self) -> np.ndarray:
        """Boolean (H, W) mask of the pixels whose ray hit something within the depth range."""
        return self.depth > 0.0


@dataclass(frozen=True)
class Shading:
    """How hit pixels are lit. The shade factor multiplies the face's sRGB colour.

    ``shade = ambient + key * max(0, n . light) + fill * max(0, -n . light) + headlight * |cos a|``,
    with the normal ``n`` turned towards the camera (surfaces are two-sided) and ``a`` the angle between
    the ray and ``n``: a key light, a weaker fill light from the opposite direction (so ceilings and
    the far sides of objects are not flat), and a light at the camera. Fog then blends the colour
    towards `background` by ``fog * (1 - exp(-depth / fog_distance))``, and pixels on an outline
    (a depth jump of more than `edge_jump` of the depth, or a change of instance or terrain class)
    are multiplied by `edge_shade`.

    Parameters
    ----------
    light : tuple of float
        World direction towards the key light; normalised on use.
    ambient, key, fill, headlight : float
        Weights of the lighting terms, all >= 0.
    fog, fog_distance : float
        Fog strength at infinity in [0, 1], and its distance scale in meters (> 0).
    edge_shade : float
        Factor for outline pixels in [0, 1]; 1 disables outlines.
    edge_jump : float
        Relative depth jump that counts as an outline (> 0).
    background : tuple of int
        sRGB colour where nothing is hit, also the fog colour.
    terrain_lighten : float
        Dark terrain class colours are lifted towards white, by ``terrain_lighten * (1 - luma)``
        (luma of the colour in [0, 1]); `terrain_lighten` is in [0, 1]. Class colours are chosen to
        read in bird's-eye views, where walls are dark; seen from inside a room, lighter walls read
        better, while light floors and ceilings stay as they are.
    """

    light: tuple[float, float, float] = (0.35, 0.55, 0.76)
    ambient: float = 0.42
    key: float = 0.40
    fill: float = 0.15
    headlight: float = 0.28
    fog: float = 0.35
    fog_distance: float = 60.0
    edge_shade: float = 0.72
    edge_jump: float = 0.06
    background: tuple[int, int, int] = (206, 220, 236)
    terrain_lighten: float = 0.4

    def __post_init__(self) -> None:
        light = np.asarray(self.light, dtype=np.float64)
        if light.shape != (3,) or not np.isfinite(light).all() or np.linalg.norm(light) < 1e-9:
            raise ValueError(f"light must be a non-zero 3-vector, got {self.light!r}")
        for name in ("ambient", "key", "fill", "headlight"):
            if not getattr(self, name) >= 0.0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)!r}")
        if not 0.0 <= self.fog <= 1.0 or not self.fog_distance > 0.0:
            raise ValueError("fog must be in [0, 1] and fog_distance > 0")
        if not 0.0 <= self.edge_shade <= 1.0 or not self.edge_jump > 0.0:
            raise ValueError("edge_shade must be in [0, 1] and edge_jump > 0")
        if not 0.0 <= self.terrain_lighten <= 1.0:
            raise ValueError(f"terrain_lighten must be in [0, 1], got {self.terrain_lighten!r}")
        if len(self.background) != 3 or not all(0 <= int(c) <= 255 for c in self.background):
            raise ValueError(f"background must be an sRGB triple in 0..255, got {self.background!r}")


def _unit_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit face normals (counter-clockwise winding); zero for degenerate faces."""
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return np.divide(normals, length, out=np.zeros_like(normals), where=length > 0)


class SceneRenderer:
    """Ray-cast camera images of one scene.

    Parameters
    ----------
    scene : Scene
        The scene; its geometry is copied into the ray-casting structure once, here.
    intrinsics : CameraIntrinsics
        Image size and pinhole parameters (default: 640 x 480, 90 degrees horizontal field of view).
    depth_range : tuple of float
        ``(near, far)`` in meters of z-depth, ``0 < near < far``; hits beyond `far` count as nothing
        hit, geometry nearer than `near` is clipped away.
    hidden_classes : sequence of str
        Terrain classes left out of the images (e.g. ``("ceiling",)`` for a view from above); names
        the scene does not have are ignored, so one list serves every scene.
    shading : Shading
        Lighting parameters.
    threads : int
        Ray-casting threads; 0 uses every core.

    Raises
    ------
    ValueError
        If `depth_range` is not ``0 < near < far`` with finite values.

    Notes
    -----
    A renderer reuses one ray buffer between frames, so it is not thread-safe: give each thread its
    own renderer (the ray casting itself already runs on every core).
    """

    def __init__(
        self,
        scene: Scene,
        *,
        intrinsics: CameraIntrinsics = DEFAULT_INTRINSICS,
        depth_range: tuple[float, float] = (0.1, 1000.0),
        hidden_classes: Sequence[str] = (),
        shading: Shading = Shading(),
        threads: int = 0,
    ) -> None:
        near, far = (float(v) for v in depth_range)
        if not (math.isfinite(near) and math.isfinite(far) and 0.0 < near < far):
            raise ValueError(f"depth_range must be (near, far) with 0 < near < far, got {depth_range!r}")
        self._intrinsics = intrinsics
        self._near, self._far = near, far
        self._shading = shading
        self._threads = int(threads)
        if isinstance(hidden_classes, str):
            hidden_classes = (hidden_classes,)
        labeled = scene.world_mesh(include_objects=True, exclude_classes=hidden_classes)
        self._class_names = labeled.class_names
        mesh = labeled.mesh
        num_faces = mesh.num_faces
        if num_faces:
            lo, hi = mesh.bounds()
            self._origin = np.round(0.5 * (lo + hi), 3)
        else:
            self._origin = np.zeros(3)

        # Per-face tables with one extra row, index `num_faces`, for pixels that hit nothing.
        self._miss = num_faces
        face_colors = _face_colors(scene, hidden_classes, lighten=shading.terrain_lighten)
        if len(face_colors) != num_faces:  # both follow Scene.world_mesh's order: surfaces, then objects
            raise AssertionError("face colours and the world mesh disagree on the number of faces")
        self._background = np.asarray(shading.background, dtype=np.float32)
        colors = np.vstack([face_colors, self._background[None]])
        self._channels = [np.ascontiguousarray(colors[:, c]) for c in range(3)]
        self._instance = np.append(labeled.instance_id, np.int32(BACKGROUND_ID)).astype(np.int32)
        self._terrain = np.append(labeled.class_index, np.int16(BACKGROUND_CLASS)).astype(np.int16)
        normals = np.zeros((num_faces + 1, 3), dtype=np.float32)
        normals[:num_faces] = _unit_normals(mesh.vertices, mesh.faces)
        self._normals = normals
        light = np.asarray(shading.light, dtype=np.float64)
        self._n_dot_light = (normals.astype(np.float64) @ (light / np.linalg.norm(light))).astype(np.float32)

        self._raycaster = o3d.t.geometry.RaycastingScene()
        if num_faces:
            self._raycaster.add_triangles(
                o3d.core.Tensor((mesh.vertices - self._origin).astype(np.float32)),
                o3d.core.Tensor(mesh.faces.astype(np.uint32)),
            )

        # Camera-frame ray directions (optical z = 1) and their inverse lengths, once per renderer.
        dirs = intrinsics.ray_directions()
        self._x = np.ascontiguousarray(dirs[0, :, 0], dtype=np.float32)
        self._y = np.ascontiguousarray(dirs[:, 0, 1], dtype=np.float32)
        self._inv_length = (1.0 / np.linalg.norm(dirs, axis=-1)).astype(np.float32)
        self._rays = np.empty((intrinsics.height, intrinsics.width, 6), dtype=np.float32)

    @property
    def intrinsics(self) -> CameraIntrinsics:
        """The camera's intrinsics."""
        return self._intrinsics

    @property
    def depth_range(self) -> tuple[float, float]:
        """``(near, far)`` in meters."""
        return (self._near, self._far)

    @property
    def shading(self) -> Shading:
        """The lighting parameters."""
        return self._shading

    @property
    def class_names(self) -> tuple[str, ...]:
        """Terrain class names; ``Frame.terrain`` indexes into this tuple."""
        return self._class_names

    @property
    def origin(self) -> np.ndarray:
        """World point subtracted from all geometry before casting (float32 precision)."""
        return self._origin.copy()

    def render(self, camera_to_world: ArrayLike) -> Frame:
        """Render one frame.

        Parameters
        ----------
        camera_to_world : array_like, shape (4, 4)
            Pose of the optical frame (x right, y down, z forward) in the world.

        Returns
        -------
        Frame
            Newly allocated images (the renderer keeps no reference to them).

        Raises
        ------
        ValueError
            If `camera_to_world` is not a finite 4x4 rigid transform.
        """
        return self._shade(self._cast(check_pose(camera_to_world)))

    def render_batch(self, camera_to_world: Iterable[ArrayLike]) -> list[Frame]:
        """Render several frames; every pose is checked before any is rendered.

        Parameters
        ----------
        camera_to_world : iterable of array_like, each shape (4, 4), or ndarray of shape (B, 4, 4)
            Poses of the optical frame.

        Returns
        -------
        list of Frame
            One frame per pose, in order.
        """
        poses = [check_pose(p) for p in camera_to_world]
        return [self._shade(self._cast(pose)) for pose in poses]

    def _cast(self, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Cast the pixel rays of `pose`; return the ray parameter (z-depth past the near plane) and face."""
        rotation = pose[:3, :3].astype(np.float32)
        eye = (pose[:3, 3] - self._origin).astype(np.float32)
        # World direction of pixel (row, col) = x[col] * R[:, 0] + y[row] * R[:, 1] + R[:, 2].
        per_row = self._y[:, None] * rotation[:, 1] + rotation[:, 2]
        per_col = self._x[:, None] * rotation[:, 0]
        near = np.float32(self._near)
        origin_row, origin_col = eye + near * per_row, near * per_col  # rays start on the near plane
        rays = self._rays
        for k in range(3):  # one 2-D broadcast per channel: much faster than a (H, W, 3) broadcast
            np.add(per_row[:, k, None], per_col[None, :, k], out=rays[..., 3 + k])
            np.add(origin_row[:, k, None], origin_col[None, :, k], out=rays[..., k])
        result = self._raycaster.cast_rays(o3d.core.Tensor.from_numpy(rays), nthreads=self._threads)
        return result["t_hit"].numpy(), result["primitive_ids"].numpy()

    def _shade(self, hits: tuple[np.ndarray, np.ndarray]) -> Frame:
        """Turn the hits of the last cast (whose rays are still in the buffer) into the four images."""
        t_hit, face = hits
        shading = self._shading
        depth = t_hit + np.float32(self._near)
        missed = ~(depth <= self._far)  # inf (no hit) compares False
        np.copyto(face, np.uint32(self._miss), where=missed)
        np.copyto(depth, np.float32(0.0), where=missed)
        semantic = self._instance.take(face)
        terrain = self._terrain.take(face)

        # Lighting: cosine between ray and normal (for the headlight and the side facing the camera).
        normals = self._normals.take(face, axis=0)
        n_dot_ray = np.einsum("ijk,ijk->ij", normals, self._rays[..., 3:])
        side = np.sign(n_dot_ray)
        np.negative(side, out=side)  # +1 where the normal as stored faces the camera
        facing_light = self._n_dot_light.take(face)
        facing_light *= side  # cosine to the light of the side seen
        shade = np.abs(n_dot_ray, out=n_dot_ray)
        shade *= self._inv_length
        shade *= np.float32(shading.headlight)
        shade += np.float32(shading.ambient)
        # key * max(0, c) + fill * max(0, -c) == (key + fill) * max(0, c) - fill * c
        shade -= np.float32(shading.fill) * facing_light
        np.maximum(facing_light, 0.0, out=facing_light)
        facing_light *= np.float32(shading.key + shading.fill)
        shade += facing_light
        if shading.edge_shade < 1.0:
            edges = _outlines(depth, semantic, terrain, jump=shading.edge_jump)
            shade[edges] *= np.float32(shading.edge_shade)
        np.copyto(shade, np.float32(1.0), where=missed)

        fog = None
        if shading.fog > 0.0:
            fog = np.multiply(depth, np.float32(-1.0 / shading.fog_distance))
            np.exp(fog, out=fog)
            fog -= np.float32(1.0)
            fog *= np.float32(-shading.fog)  # fog * (1 - exp(-depth / distance)); 0 where missed
            shade *= np.float32(1.0) - fog
        rgb = np.empty((*face.shape, 3), dtype=np.uint8)
        channel = np.empty(face.shape, dtype=np.float32)
        for c in range(3):  # 2-D operations per channel are faster than (H, W, 3) broadcasts
            self._channels[c].take(face, out=channel)
            channel *= shade
            if fog is not None:
                channel += fog * self._background[c]
            np.clip(channel, 0.0, 255.0, out=channel)
            np.rint(channel, out=channel)
            rgb[..., c] = channel
        return Frame(rgb=rgb, depth=depth, semantic=semantic, terrain=terrain)


def _outlines(depth: np.ndarray, semantic: np.ndarray, terrain: np.ndarray, *, jump: float) -> np.ndarray:
    """Pixels on the near side of a depth jump or label change to their right or lower neighbour."""
    far = np.where(depth > 0.0, depth, np.float32(np.inf))
    edges = np.zeros(depth.shape, dtype=bool)
    for axis in (0, 1):
        a = [slice(None), slice(None)]
        b = [slice(None), slice(None)]
        a[axis], b[axis] = slice(None, -1), slice(1, None)
        za, zb = far[tuple(a)], far[tuple(b)]
        with np.errstate(invalid="ignore"):
            differ = np.abs(za - zb) > jump * np.minimum(za, zb)
        differ |= semantic[tuple(a)] != semantic[tuple(b)]
        differ |= terrain[tuple(a)] != terrain[tuple(b)]
        a_nearer = za <= zb
        edges[tuple(a)] |= differ & a_nearer
        edges[tuple(b)] |= differ & ~a_nearer
    return edges


def _face_colors(scene: Scene, hidden_classes: Sequence[str], *, lighten: float) -> np.ndarray:
    """Per-face sRGB colours in the order of ``Scene.world_mesh``: surfaces (class colours), then objects."""
    hidden = set(hidden_classes)
    parts: list[np.ndarray] = []
    class_colors = scene.annotations.terrain_classes
    for surface in scene.surfaces:
        if surface.terrain_class in hidden:
            continue
        color = np.asarray(class_colors[surface.terrain_class].color, dtype=np.float32)
        luma = float(color @ _LUMA) / 255.0
        color += (255.0 - color) * np.float32(lighten * (1.0 - luma))
        parts.append(np.broadcast_to(color, (surface.mesh.num_faces, 3)))
    for obj in scene.objects:
        if obj.mesh.face_colors is not None:
            parts.append(obj.mesh.face_colors.astype(np.float32))
        else:
            color = np.asarray(default_color(obj.annotation.category), dtype=np.float32)
            parts.append(np.broadcast_to(color, (obj.mesh.num_faces, 3)))
    return np.concatenate(parts) if parts else np.zeros((0, 3), dtype=np.float32)
