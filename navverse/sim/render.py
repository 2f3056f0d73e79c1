"""The robot's camera: RGB, depth, instance and terrain images of a scene, ray-cast on the CPU.

:class:`SceneRenderer` puts every terrain surface (ceilings included: a camera inside a building
sees them) and every object of a :class:`~navverse.scene.geometry.Scene` into one
:class:`~navverse.sim.raycast.TriangleCaster` (Embree, rays in packets of eight) once, then casts one
ray per pixel per frame through the pixel centres of a pinhole camera
(:class:`~navverse.sim.camera.CameraIntrinsics`). The per-pixel directions are computed once; a frame
only rotates and translates them. Rays are cast in a local frame centred on the scene, so float32
keeps sub-millimetre precision far from the world origin.

Each hit pixel takes the colour of its face (objects: their per-face colours, or their category colour
when the mesh has none; terrain: the colour of its class, dark ones lifted a little) or, on a textured
face, the bilinear sample of its texture at the hit's interpolated UV (repeating outside 0..1), shaded by
:class:`Shading`: an ambient term, Lambert from a fixed key light and a weaker opposite fill light, a
headlight at the camera, a slight fog towards the background colour with distance, and a darker line
where depth jumps or the label changes (outlines that make furniture stand out against walls of a
similar colour). Pixels that hit nothing show the background colour or, with ``Shading.sky``, a sky
graded by the ray's elevation (the default for outdoor and ``i2o`` scenes). Every texture of the scene
is packed once into one flat texel pool (an atlas without resizing), so sampling is index arithmetic;
scenes without textures skip it entirely. These flat images are vectorised numpy on preallocated
tables.

By default the images are lit instead, by a look (:mod:`navverse.look`): each hit's material tile
(:class:`~navverse.sim.tile_sampler.TileSampler`), facade paint, markings or object colour, times the
light of :class:`~navverse.sim.lighting.Lighting` (sun and shadow rays, sky, room lamps), exposed and
tone mapped; its per-hit loops are compiled (:mod:`navverse.sim.shade_kernels`). Either way there is no
global state, and rendering is deterministic: the same scene, camera and pose give the same bytes.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from navverse.look.materials import MATERIALS, srgb_to_linear
from navverse.look.scene_look import SceneLook, SurfaceLook, scene_look
from navverse.look.settings import EVAL_LOOK, LookSettings
from navverse.scene.colors import default_color
from navverse.scene.geometry import MeshData, Scene, merge_textures, unit_face_normals
from navverse.scene_types import scene_profile
from navverse.sim import shade_kernels as kernels
from navverse.sim.camera import CameraIntrinsics, check_pose
from navverse.sim.lighting import ImageHits, Lighting
from navverse.sim.raycast import TriangleCaster
from navverse.sim.tile_sampler import TileSampler

__all__ = [
    "BACKGROUND_CLASS",
    "BACKGROUND_ID",
    "DEFAULT_INTRINSICS",
    "FLAT_COLOR",
    "IMAGE_TEXTURE",
    "NOTHING_HIT",
    "Frame",
    "SceneRenderer",
    "Shading",
]

BACKGROUND_ID = 0
"""``Frame.semantic`` where no object was hit (terrain or background)."""
BACKGROUND_CLASS = -1
"""``Frame.terrain`` where no terrain surface was hit (an object or the background)."""
FLAT_COLOR = -1
""":meth:`SceneRenderer.materials` where a face shows only its own colour, no material."""
IMAGE_TEXTURE = -2
""":meth:`SceneRenderer.materials` where a scene's image texture shows (storefront signs)."""
NOTHING_HIT = -3
""":meth:`SceneRenderer.materials` where the ray hit nothing."""

DEFAULT_INTRINSICS = CameraIntrinsics.from_hfov()
"""640 x 480 pixels, 90 degrees horizontal field of view, square pixels, centred principal point."""

_LUMA = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)  # Rec. 709 weights
Component = Literal["radiance", "albedo", "light"]
"""What :meth:`SceneRenderer.radiance` returns: the radiance or one of its factors."""
_CHUNK = 16384  # textured hits sampled per pass: the per-hit buffers stay in the CPU cache


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

    ``shade = ambient + key * max(0, n . light) + fill * max(0, -n . light) + headlight * |cos a|``
    (on a textured face it multiplies the sampled texel colour instead),
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
        sRGB colour where nothing is hit (without `sky`), also the fog colour.
    terrain_lighten : float
        Dark terrain class colours are lifted towards white, by ``terrain_lighten * (1 - luma)``
        (luma of the colour in [0, 1]); `terrain_lighten` is in [0, 1]. Class colours are chosen to
        read in bird's-eye views, where walls are dark; seen from inside a room, lighter walls read
        better, while light floors and ceilings stay as they are.
    sky : bool
        Pixels that hit nothing show a sky instead of `background`: `sky_horizon` at and below the
        horizon, blending linearly in the sine of the ray's elevation to `sky_zenith` straight up
        (world +z). Sky pixels get no fog and no outline.
    sky_horizon, sky_zenith : tuple of int
        sRGB colours of the sky at the horizon and at the zenith.
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
    sky: bool = False
    sky_horizon: tuple[int, int, int] = (200, 214, 230)
    sky_zenith: tuple[int, int, int] = (110, 150, 205)

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
        for name in ("background", "sky_horizon", "sky_zenith"):
            color = getattr(self, name)
            if len(color) != 3 or not all(0 <= int(c) <= 255 for c in color):
                raise ValueError(f"{name} must be an sRGB triple in 0..255, got {color!r}")


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
    shading : Shading, optional
        Lighting parameters; by default ``Shading()``, with the sky on for ``outdoor`` and ``i2o``
        scenes.
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
        shading: Shading | None = None,
        look: LookSettings | SceneLook | None = None,
        threads: int = 0,
    ) -> None:
        near, far = (float(v) for v in depth_range)
        if not (math.isfinite(near) and math.isfinite(far) and 0.0 < near < far):
            raise ValueError(f"depth_range must be (near, far) with 0 < near < far, got {depth_range!r}")
        if shading is not None and look is not None:
            raise ValueError("give a look (lit images) or a shading (flat images), not both")
        sky = scene_profile(scene.annotations.scene_type).sky
        flat = shading is not None
        if shading is None:
            shading = Shading(sky=sky, terrain_lighten=0.0)
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
        textures = _texture_tables(scene, hidden_classes)  # None: no textured face
        self._sampler = None
        if textures is not None:
            if len(textures.face_texture) != num_faces + 1:
                raise AssertionError("face textures and the world mesh disagree on the number of faces")
            self._sampler = _TextureSampler(textures, intrinsics.width * intrinsics.height)
        colors = np.vstack([face_colors, self._background[None]])
        self._channels = [np.ascontiguousarray(colors[:, c]) for c in range(3)]
        self._instance = np.append(labeled.instance_id, np.int32(BACKGROUND_ID)).astype(np.int32)
        self._terrain = np.append(labeled.class_index, np.int16(BACKGROUND_CLASS)).astype(np.int16)
        normals = np.zeros((num_faces + 1, 3), dtype=np.float32)
        normals[:num_faces] = unit_face_normals(mesh.vertices, mesh.faces)
        self._normals = normals
        light = np.asarray(shading.light, dtype=np.float64)
        self._n_dot_light = (normals.astype(np.float64) @ (light / np.linalg.norm(light))).astype(np.float32)

        self._caster = TriangleCaster(
            (mesh.vertices - self._origin).astype(np.float32), mesh.faces, threads=self._threads
        )
        # Moving bodies (add_body_shape / place_bodies): per shape its normals, first table row and slots.
        self._body_shapes: list[_BodyShape] = []
        self._body_rows = np.zeros(0, dtype=np.int64)  # per placed body: the table row of its face 0

        # Camera-frame ray directions (optical z = 1) and their inverse lengths, once per renderer.
        dirs = intrinsics.ray_directions()
        self._x = np.ascontiguousarray(dirs[0, :, 0], dtype=np.float32)
        self._y = np.ascontiguousarray(dirs[:, 0, 1], dtype=np.float32)
        self._inv_length = (1.0 / np.linalg.norm(dirs, axis=-1)).astype(np.float32)
        self._rays = np.empty((intrinsics.height, intrinsics.width, 6), dtype=np.float32)
        self._lighting: Lighting | None = None
        if not flat:
            if not isinstance(look, SceneLook):
                look = scene_look(scene, look or EVAL_LOOK, hidden_classes=tuple(hidden_classes))
            geo = scene.annotations.geo
            self._latitude = None if geo is None else geo.origin_lat
            self._sky_shown = sky
            self.set_look(look)
            self._tiles = TileSampler(look.tiles, look.tile_sizes)
            self._linear = np.ascontiguousarray(srgb_to_linear(colors).T, dtype=np.float32)  # (3, F + 1)
            self._to_linear = srgb_to_linear(np.arange(256))
            self._pixel_angle = 1.0 / intrinsics.fx
            self._grain_base = srgb_to_linear(MATERIALS["object_grain"].color)

    def set_look(self, look: LookSettings | SceneLook) -> None:
        """Render lit images with another look from now on.

        Parameters
        ----------
        look : LookSettings or SceneLook
            Settings (the current look's scene and map under them: cheap) or a look compiled for this
            renderer's scene and hidden classes.

        Raises
        ------
        ValueError
            If the renderer makes flat images, or `look` was compiled for other faces.
        """
        if isinstance(look, LookSettings):
            if self._lighting is None:
                raise ValueError("a renderer made with a shading makes flat images: it has no look")
            look = self._look.with_settings(look)
        if len(look.face_kind) != self._miss + 1:
            raise ValueError("the look was compiled for other faces (another scene or other hidden classes)")
        self._look = look
        self._lighting = Lighting(
            look.settings,
            rooms=look.rooms,
            latitude_deg=self._latitude,
            caster=self._caster,
            origin=self._origin,
            sky=self._sky_shown,
            threads=self._threads,
        )

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
        """The flat-image parameters (their sky and background also serve lit images)."""
        return self._shading

    @property
    def look(self) -> LookSettings | None:
        """The look of lit images; None when the renderer makes flat ones (a `shading` was given)."""
        return None if self._lighting is None else self._lighting.settings

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

    def add_body_shape(self, mesh: MeshData, *, max_bodies: int) -> int:
        """Add a shape moving bodies can take (people, cars): a mesh in its own frame, its faces in their
        colours, with room for `max_bodies` of it in a frame. Returns its index for :meth:`place_bodies`.

        Raises
        ------
        ValueError
            If the mesh has no face or `max_bodies` is not positive.
        """
        if mesh.num_faces == 0 or max_bodies < 1:
            raise ValueError("a body shape needs faces and room for at least one body")
        first = len(self._instance)
        rows = mesh.num_faces * int(max_bodies)
        colors = np.tile(_mesh_face_colors(mesh), (max_bodies, 1)).astype(np.float32)
        for c in range(3):
            self._channels[c] = np.concatenate([self._channels[c], colors[:, c]])
        if self._lighting is not None:
            linear = np.ascontiguousarray(srgb_to_linear(colors).T, dtype=np.float32)
            self._linear = np.ascontiguousarray(np.concatenate([self._linear, linear], axis=1))
        self._instance = np.concatenate([self._instance, np.full(rows, BACKGROUND_ID, np.int32)])
        self._terrain = np.concatenate([self._terrain, np.full(rows, BACKGROUND_CLASS, np.int16)])
        self._normals = np.concatenate([self._normals, np.zeros((rows, 3), np.float32)])
        self._n_dot_light = np.concatenate([self._n_dot_light, np.zeros(rows, np.float32)])
        normals = unit_face_normals(mesh.vertices, mesh.faces).astype(np.float64)
        caster_shape = self._caster.add_shape(np.asarray(mesh.vertices, np.float32), mesh.faces)
        self._body_shapes.append(_BodyShape(caster_shape, normals, first, int(max_bodies)))
        return len(self._body_shapes) - 1

    def place_bodies(self, shapes: ArrayLike, transforms: ArrayLike, semantic_ids: ArrayLike) -> None:
        """Show these moving bodies in the frames rendered from now on (replacing the last ones): body
        ``i`` is shape ``shapes[i]`` (:meth:`add_body_shape`) placed by the rigid world transform
        ``transforms[i]`` (4 x 4, shape frame to world), with semantic id ``semantic_ids[i]``.

        Raises
        ------
        ValueError
            If a shape is unknown, more bodies of a shape are given than it has room for, or the arrays
            do not match.
        """
        kinds = np.asarray(shapes, dtype=np.int64).reshape(-1)
        matrices = np.asarray(transforms, dtype=np.float64).reshape(-1, 4, 4)
        ids = np.asarray(semantic_ids, dtype=np.int32).reshape(-1)
        if not len(kinds) == len(matrices) == len(ids):
            raise ValueError("give one shape, one transform and one semantic id per body")
        if len(kinds) and (kinds.min() < 0 or kinds.max() >= len(self._body_shapes)):
            raise ValueError(f"unknown body shape; {len(self._body_shapes)} were added")
        local = matrices.copy()
        local[:, :3, 3] -= self._origin
        rows = np.zeros(len(kinds), dtype=np.int64)
        light = np.asarray(self._shading.light, dtype=np.float64)
        light /= np.linalg.norm(light)
        for index, shape in enumerate(self._body_shapes):
            mine = np.flatnonzero(kinds == index)
            if len(mine) > shape.slots:
                raise ValueError(f"{len(mine)} bodies of shape {index}, which has room for {shape.slots}")
            faces = len(shape.normals)
            rows[mine] = shape.first + faces * np.arange(len(mine))
            if not len(mine):
                continue
            turned = np.einsum("bij,fj->bfi", matrices[mine, :3, :3], shape.normals).reshape(-1, 3)
            span = slice(shape.first, shape.first + faces * len(mine))
            self._normals[span] = turned
            self._n_dot_light[span] = turned @ light
            self._instance[span] = np.repeat(ids[mine], faces)
        self._caster.set_instances([self._body_shapes[k].caster_shape for k in kinds], local)
        self._body_rows = rows

    def sees(self, eye: ArrayLike, points: ArrayLike, *, max_distance: float = math.inf) -> np.ndarray:
        """Whether each world point ``(K, 3)`` is in plain sight of the world point `eye`: within
        `max_distance` and with nothing of the scene (static or placed bodies) between them, in any
        direction (not only a camera's field of view).

        Returns
        -------
        ndarray of bool, shape (K,)
        """
        targets = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        start = np.asarray(eye, dtype=np.float64).reshape(3)
        offsets = targets - start
        rays = np.concatenate([np.broadcast_to(start - self._origin, offsets.shape), offsets], axis=1)
        blocked = self._caster.occluded(rays.astype(np.float32), tfar=1.0 - 1e-4)
        return ~blocked & (np.linalg.norm(offsets, axis=1) <= max_distance)

    def _cast(self, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Cast the pixel rays of `pose`; return the ray parameter (z-depth past the near plane), the face
        and the barycentric ``(u, v)`` of the hit in it (hit = ``(1-u-v) p0 + u p1 + v p2``)."""
        rotation = pose[:3, :3].astype(np.float32)
        eye = (pose[:3, 3] - self._origin).astype(np.float32)
        # World direction of pixel (row, col) = x[col] * R[:, 0] + y[row] * R[:, 1] + R[:, 2]; rays start
        # on the near plane.
        kernels.split(
            kernels.pixel_rays,
            len(self._y),
            self._x,
            self._y,
            rotation,
            eye,
            self._near,
            self._rays,
            parts=self._threads,
        )
        hits = self._caster.cast(self._rays)
        face = hits.face
        if len(self._body_rows):
            on_body = hits.instance >= 0
            face[on_body] = (self._body_rows[hits.instance[on_body]] + face[on_body]).astype(face.dtype)
        return hits.t_hit, face, hits.barycentric

    def _depth(self, t_hit: np.ndarray, face: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The z-depth image of a cast (0 where nothing was hit within the depth range) and the mask of
        those misses; `face` is set to the miss row there."""
        depth = t_hit + np.float32(self._near)
        missed = ~(depth <= self._far)  # inf (no hit) compares False
        np.copyto(face, np.uint32(self._miss), where=missed)
        np.copyto(depth, np.float32(0.0), where=missed)
        return depth, missed

    def _shade(self, hits: tuple[np.ndarray, np.ndarray, np.ndarray]) -> Frame:
        """Turn the hits of the last cast (whose rays are still in the buffer) into the four images."""
        t_hit, face, barycentric = hits
        depth, missed = self._depth(t_hit, face)
        semantic = self._instance.take(face)
        terrain = self._terrain.take(face)
        if self._lighting is None:
            rgb = self._flat_rgb(face, barycentric, depth, missed, semantic, terrain)
        else:
            rgb = self._lit_rgb(t_hit, face, barycentric, missed)
        return Frame(rgb=rgb, depth=depth, semantic=semantic, terrain=terrain)

    def _flat_rgb(
        self,
        face: np.ndarray,
        barycentric: np.ndarray,
        depth: np.ndarray,
        missed: np.ndarray,
        semantic: np.ndarray,
        terrain: np.ndarray,
    ) -> np.ndarray:
        """Flat images (:class:`Shading`): face colours under fixed lights, fog and outlines."""
        shading = self._shading
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
        # Pixels whose colour is not their face's: textured hits and, with a sky, misses (shade 1, no fog).
        overrides: list[tuple[np.ndarray, list[np.ndarray]]] = []
        if self._sampler is not None:
            overrides.append(self._sampler.sample(face, barycentric))
        if shading.sky:
            overrides.append(self._sky(missed))
        rgb = np.empty((*face.shape, 3), dtype=np.uint8)
        channel = np.empty(face.shape, dtype=np.float32)
        for c in range(3):  # 2-D operations per channel are faster than (H, W, 3) broadcasts
            self._channels[c].take(face, out=channel)
            for pixels, colors in overrides:
                channel.put(pixels, colors[c])
            channel *= shade
            if fog is not None:
                channel += fog * self._background[c]
            np.clip(channel, 0.0, 255.0, out=channel)
            np.rint(channel, out=channel)
            rgb[..., c] = channel
        return rgb

    def _lit_rgb(
        self,
        t_hit: np.ndarray,
        face: np.ndarray,
        barycentric: np.ndarray,
        missed: np.ndarray,
    ) -> np.ndarray:
        """Lit images (the look's :class:`~navverse.sim.lighting.Lighting`): albedo times light, exposed."""
        lighting = self._lighting
        assert lighting is not None
        height, width = face.shape
        radiance = self._lit_radiance(t_hit, face, barycentric, missed)
        flat_missed = missed.reshape(-1)
        sky = self._shading.sky and bool(flat_missed.any())
        rgb = lighting.encode(radiance, measured=None if sky or flat_missed.all() else ~flat_missed)
        if not sky and flat_missed.any():
            rgb[flat_missed] = np.asarray(self._shading.background, dtype=np.uint8)  # the void: no light
        return rgb.reshape(height, width, 3)

    def radiance(self, camera_to_world: ArrayLike, *, component: Component = "radiance") -> np.ndarray:
        """The linear radiance a lit renderer sees from a pose, before exposure and tone mapping, or
        one of its two factors.

        Parameters
        ----------
        camera_to_world : array_like, shape (4, 4)
            Pose of the optical frame.
        component : {"radiance", "albedo", "light"}
            The radiance, or the albedo of what each pixel sees (materials, textures, colours), or the
            light falling on it (irradiance: sun, sky, lamps, shadows), whose product it is (before
            mirrored sky and haze).

        Returns
        -------
        ndarray of float32, shape (H, W, 3)
            Linear RGB (radiance 1.0: a white surface in the open sky's light); the sky where a scene
            has one, 0 where nothing is hit in a scene without (0 for the factors).

        Raises
        ------
        ValueError
            If the renderer makes flat images (a `shading` was given) or the pose is not rigid.
        """
        t_hit, face, barycentric, missed = self._lit_cast(camera_to_world, "radiance")
        height, width = face.shape
        radiance = self._lit_radiance(t_hit, face, barycentric, missed, component)
        return radiance.T.reshape(height, width, 3)

    def _lit_radiance(
        self,
        t_hit: np.ndarray,
        face: np.ndarray,
        barycentric: np.ndarray,
        missed: np.ndarray,
        component: Component = "radiance",
    ) -> np.ndarray:
        """The ``(3, H * W)`` linear radiance of the last cast: albedo (materials, textures, object
        colours) times the look's light; the sky or 0 where nothing was hit. With `component`
        ``"albedo"`` or ``"light"``, only that factor at the hits (0 elsewhere)."""
        lighting = self._lighting
        assert lighting is not None
        height, width = face.shape
        at = self._hit_surfaces(t_hit, face, missed)
        hits, albedo, surface = at.hits, at.albedo, at.surface
        self._tiles.sample_into(
            albedo, surface.tile, surface.u, surface.v, at.footprint, shift=self._look.shift,
            tint=self._look.tint, modulate=surface.modulate, grain_base=self._grain_base,
            parts=self._threads,
        )  # fmt: skip
        if self._sampler is not None:
            pixels, colors = self._sampler.sample(face, barycentric)
            if len(pixels):
                slot = np.searchsorted(hits, pixels)  # textured pixels are hits
                for c in range(3):
                    albedo[c, slot] = self._to_linear.take(np.rint(colors[c]).astype(np.intp).clip(0, 255))
        radiance = np.zeros((3, height * width), dtype=np.float32)
        light = lighting.irradiance(
            at.points, at.normals, at.depth, at.room, image=ImageHits(hits, at.face, width, height)
        )
        if component == "light":
            radiance[:, hits] = light
        elif component == "albedo":
            radiance[:, hits] = albedo
        else:
            lighting.shade(radiance, hits, albedo, light, at.depth, surface.reflect)
        if self._shading.sky and component == "radiance" and len(hits) < height * width:
            lighting.sky(radiance, np.flatnonzero(missed.reshape(-1)), self._rays.reshape(-1, 6))
        return radiance

    def _lit_cast(
        self, camera_to_world: ArrayLike, what: str
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Cast a pose for a lit-only image `what`: the hits and the mask of misses."""
        if self._lighting is None:
            raise ValueError(f"a renderer made with a shading has no {what}: make it with a look")
        t_hit, face, barycentric = self._cast(check_pose(camera_to_world))
        _, missed = self._depth(t_hit, face)
        return t_hit, face, barycentric, missed

    def _hit_surfaces(self, t_hit: np.ndarray, face: np.ndarray, missed: np.ndarray) -> _Hits:
        """The hits of the last cast: where they are, their faces' colours and what their look shows."""
        flat_face = face.reshape(-1)
        hits = np.flatnonzero(~missed.reshape(-1))
        count = len(hits)
        points = np.empty((count, 3), dtype=np.float32)
        world = np.empty((count, 3), dtype=np.float64)
        normals = np.empty((count, 3), dtype=np.float32)
        depth = np.empty(count, dtype=np.float32)
        footprint = np.empty(count, dtype=np.float32)
        hit_face = np.empty(count, dtype=flat_face.dtype)
        albedo = np.empty((3, count), dtype=np.float32)
        kernels.split(
            kernels.gather_hits, count,
            self._rays.reshape(-1, 6), t_hit.reshape(-1), hits, flat_face, self._normals, self._linear,
            self._origin, self._near, self._pixel_angle, points, world, normals, depth, footprint,
            hit_face, albedo, parts=self._threads,
        )  # fmt: skip
        room = self._look.room_of(world, normals)
        # A moving body's face shows as an object's does (the look's miss row is an object).
        surface = self._look.surface(np.minimum(hit_face, self._miss), world, normals, room)
        return _Hits(hits, points, normals, depth, footprint, hit_face, albedo, room, surface)

    def materials(self, camera_to_world: ArrayLike) -> np.ndarray:
        """What material each pixel of a lit image shows, from a pose.

        Parameters
        ----------
        camera_to_world : array_like, shape (4, 4)
            Pose of the optical frame.

        Returns
        -------
        ndarray of int16, shape (H, W)
            An index into :data:`navverse.look.materials.MATERIAL_NAMES` (a procedural material, or
            what is painted on it: windows, doors, markings...), :data:`IMAGE_TEXTURE` where a
            scene texture shows (storefront signs), :data:`FLAT_COLOR` where a face shows its own
            colour only, :data:`NOTHING_HIT` where the ray hit nothing.

        Raises
        ------
        ValueError
            If the renderer makes flat images (a `shading` was given) or the pose is not rigid.
        """
        t_hit, face, barycentric, missed = self._lit_cast(camera_to_world, "materials")
        at = self._hit_surfaces(t_hit, face, missed)
        image = np.full(face.size, NOTHING_HIT, dtype=np.int16)
        image[at.hits] = np.where(at.surface.tile >= 0, at.surface.tile, FLAT_COLOR)
        if self._sampler is not None:
            image[self._sampler.sample(face, barycentric)[0]] = IMAGE_TEXTURE
        return image.reshape(face.shape)

    def _sky(self, missed: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
        """Flat indices of the missed pixels and their three sky channels, by the elevation of their rays."""
        pixels = np.flatnonzero(missed)
        sine = self._rays[..., 5].take(pixels)  # world z of the ray direction
        sine *= self._inv_length.take(pixels)
        np.clip(sine, 0.0, 1.0, out=sine)
        horizon = np.asarray(self._shading.sky_horizon, dtype=np.float32)
        zenith = np.asarray(self._shading.sky_zenith, dtype=np.float32)
        return pixels, [
            np.float32(h) + sine * np.float32(z - h) for h, z in zip(horizon, zenith, strict=True)
        ]


@dataclass(frozen=True)
class _Hits:
    """Per hit pixel of a cast (`K` of them): its pixel, local point, normal turned to the camera,
    z-depth, footprint on its surface, face, face colour (linear; the look's albedo is sampled into
    it), room and what the look shows there."""

    hits: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    depth: np.ndarray
    footprint: np.ndarray
    face: np.ndarray
    albedo: np.ndarray
    room: np.ndarray
    surface: SurfaceLook


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


@dataclass(frozen=True, eq=False)
class _TextureTables:
    """Per-face texture references and every texture of a scene packed into one planar texel pool.

    Every table is planar (one contiguous row per quantity) so that the per-pixel gathers from it give
    contiguous arrays: numpy's arithmetic on strided columns is several times slower.

    Attributes
    ----------
    face_texture : ndarray of int32, shape (F + 1,)
        Texture index per face of the world mesh, ``-1`` for untextured faces and for the extra row of
        pixels that hit nothing.
    face_texels : ndarray of float32, shape (6, F + 1)
        Per face, its texel coordinates ``x = u * width - 0.5`` and ``y = (1 - v) * height - 0.5`` (texel
        centres at whole numbers, row 0 at ``v = 1``) as ``x0, x1 - x0, x2 - x0, y0, y1 - y0, y2 - y0``
        over its corners, shifted by whole repeats of the texture to keep them small (zeros on untextured
        faces and the extra row): a hit at barycentric ``(a, b)`` is at ``x0 + a (x1 - x0) + b (x2 - x0)``.
    pool : ndarray of uint8, shape (3, N)
        The R, G and B rows of the texels of every texture, each image row-major (row 0 its top) with one
        more column and row that repeat its first ones (bilinear neighbours across the wrap), after the
        one before.
    width, height : ndarray of float32, shape (T,)
        Size of each texture in texels (without the repeated column and row).
    offset : ndarray of float32 or float64, shape (T,)
        Index in `pool` of each texture's first texel; float64 only if float32 cannot hold every index
        exactly (a pool of more than 2**24 texels).
    """

    face_texture: np.ndarray
    face_texels: np.ndarray
    pool: np.ndarray
    width: np.ndarray
    height: np.ndarray
    offset: np.ndarray


def _scene_meshes(scene: Scene, hidden_classes: Sequence[str]) -> list[MeshData]:
    """The meshes in the order of ``Scene.world_mesh``: visible surfaces, then objects (local frame)."""
    hidden = set(hidden_classes)
    surfaces = [s.mesh for s in scene.surfaces if s.terrain_class not in hidden]
    return surfaces + [obj.mesh for obj in scene.objects]


def _texture_tables(scene: Scene, hidden_classes: Sequence[str]) -> _TextureTables | None:
    """Texture tables of the scene's faces in world-mesh order; ``None`` if no face is textured.

    Textures are shared by name across meshes (one name holds one image within a scene).
    """
    meshes = _scene_meshes(scene, hidden_classes)
    if not any(m.textured for m in meshes):
        return None
    face_uvs, index, textures = merge_textures(meshes)
    images = [t.image for t in textures]
    width = np.array([image.shape[1] for image in images], dtype=np.int64)
    height = np.array([image.shape[0] for image in images], dtype=np.int64)
    face_texture = np.append(index, np.int32(-1))
    sizes = (width + 1) * (height + 1)
    offset = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    return _TextureTables(
        face_texture=face_texture,
        face_texels=_face_texels(face_uvs, face_texture[:-1], width, height),
        pool=np.concatenate([_pool_image(image) for image in images], axis=1),
        width=width.astype(np.float32),
        height=height.astype(np.float32),
        offset=offset.astype(np.float32 if sizes.sum() <= 2**24 else np.float64),
    )


def _pool_image(image: np.ndarray) -> np.ndarray:
    """`image` with its first column and row repeated after its last ones, as ``(3, pixels)`` RGB rows."""
    wrapped = np.pad(image, ((0, 1), (0, 1), (0, 0)), mode="wrap")
    return np.ascontiguousarray(wrapped.reshape(-1, 3).T)


def _face_texels(uvs: np.ndarray, texture: np.ndarray, width: np.ndarray, height: np.ndarray) -> np.ndarray:
    """The ``(6, F + 1)`` texel-coordinate rows of :class:`_TextureTables` from (F, 3, 2) UVs."""
    textured = texture >= 0
    size_x = np.where(textured, width.take(np.maximum(texture, 0)), 1).astype(np.float64)[:, None]
    size_y = np.where(textured, height.take(np.maximum(texture, 0)), 1).astype(np.float64)[:, None]
    x = uvs[..., 0].astype(np.float64) * size_x - 0.5
    y = (1.0 - uvs[..., 1].astype(np.float64)) * size_y - 0.5
    x -= size_x * np.floor(x[:, :1] / size_x)  # whole repeats: the same texels, smaller numbers
    y -= size_y * np.floor(y[:, :1] / size_y)
    table = np.zeros((6, len(texture) + 1), dtype=np.float32)
    rows = (x[:, 0], x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], y[:, 0], y[:, 1] - y[:, 0], y[:, 2] - y[:, 0])
    for k, row in enumerate(rows):
        table[k, :-1] = np.where(textured, row, 0.0)
    return table


class _TextureSampler:
    """Bilinear texture samples at the hits on textured faces, with scratch buffers reused every frame.

    Parameters
    ----------
    tables : _TextureTables
        The scene's texture tables.
    num_pixels : int
        Pixels per frame (the most hits a frame can have).

    Notes
    -----
    Not thread-safe (the buffers are shared between calls), like the renderer that owns it. The hits are
    sampled in chunks of ``_CHUNK`` so that the two dozen passes over each chunk run in the CPU cache;
    every per-hit array is contiguous (gathered from planar tables), as numpy's arithmetic on strided
    arrays is several times slower; gathers into a buffer use ``mode="clip"`` (the indices are valid by
    construction) because ``mode="raise"`` would copy through a temporary.
    """

    def __init__(self, tables: _TextureTables, num_pixels: int) -> None:
        self._tables = tables
        self._texture = np.empty(num_pixels, dtype=np.int32)
        self._mask = np.empty(num_pixels, dtype=bool)
        self._colors = np.empty((3, num_pixels), dtype=np.float32)
        n = min(int(num_pixels), _CHUNK)  # the per-hit buffers hold one chunk
        self._pairs = np.empty(n, dtype=np.uint64)  # barycentric (a, b) as one 8-byte word
        self._texels = np.empty((6, n), dtype=np.float32)
        self._scratch = np.empty((9, n), dtype=np.float32)
        self._linear = np.empty(n, dtype=tables.offset.dtype)
        self._index = np.empty((2, n), dtype=np.intp)
        self._corners = np.empty((12, n), dtype=np.uint8)

    def sample(self, face: np.ndarray, barycentric: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
        """Sample the textures under every textured hit.

        Parameters
        ----------
        face : ndarray of uint32, shape (H, W)
            Face per pixel (the miss row where nothing was hit).
        barycentric : ndarray of float32, shape (H, W, 2)
            Open3D's ``primitive_uvs``: the hit is ``(1-a-b) p0 + a p1 + b p2``.

        Returns
        -------
        pixels : ndarray of int64, shape (K,)
            Flat indices of the pixels on textured faces.
        colors : list of three ndarray of float32, shape (K,)
            Their sampled sRGB channels (repeat wrapping); views of a buffer the next call overwrites.
        """
        flat_face = face.reshape(-1)
        texture = np.take(self._tables.face_texture, flat_face, out=self._texture, mode="clip")
        pixels = np.flatnonzero(np.greater_equal(texture, 0, out=self._mask))
        pairs = np.ascontiguousarray(barycentric, dtype=np.float32).reshape(-1, 2).view(np.uint64).reshape(-1)
        colors = self._colors[:, : len(pixels)]
        for start in range(0, len(pixels), _CHUNK):
            chunk = slice(start, start + _CHUNK)
            self._sample_chunk(pixels[chunk], flat_face, texture, pairs, out=colors[:, chunk])
        return pixels, list(colors)

    def _sample_chunk(
        self, pixels: np.ndarray, face: np.ndarray, texture: np.ndarray, pairs: np.ndarray, *, out: np.ndarray
    ) -> None:
        """The colours of `pixels` (at most one chunk) into the ``(3, K)`` `out`, from the flat `face`
        and `texture` images and the barycentric `pairs` (one 8-byte word per pixel)."""
        tables = self._tables
        k = len(pixels)
        hit_face = face.take(pixels).astype(np.intp)
        hit_texture = texture.take(pixels).astype(np.intp)
        texels = self._texels[:, :k]
        for source, target in zip(tables.face_texels, texels, strict=True):
            np.take(source, hit_face, out=target, mode="clip")
        x, y, col, row, tmp, a, b, width, height = self._scratch[:9, :k]
        ab = np.take(pairs, pixels, out=self._pairs[:k], mode="clip").view(np.float32).reshape(k, 2)
        np.copyto(a, ab[:, 0])  # contiguous copies for the arithmetic
        np.copyto(b, ab[:, 1])
        _texel_coordinate(a, b, texels[:3], out=x, tmp=tmp)
        _texel_coordinate(a, b, texels[3:], out=y, tmp=tmp)
        np.take(tables.width, hit_texture, out=width, mode="clip")
        np.take(tables.height, hit_texture, out=height, mode="clip")
        _split_wrap(x, width, whole=col, tmp=tmp)  # x becomes the weight of the next column
        _split_wrap(y, height, whole=row, tmp=tmp)
        corners = self._gather_corners(row, col, width, hit_texture)
        _blend(corners, x, y, out=out, scratch=self._scratch[2:9, :k])

    def _gather_corners(
        self, row: np.ndarray, col: np.ndarray, width: np.ndarray, texture: np.ndarray
    ) -> np.ndarray:
        """The ``(12, K)`` RGB rows (``3 corner + channel``) of texel ``(row, col)`` of `texture` and of its
        right, lower and lower-right neighbours (the pool's extra column and row hold the wrap)."""
        k = len(row)
        linear = self._linear[:k]
        np.add(width, 1, out=linear, dtype=linear.dtype)  # row stride
        linear *= row
        linear += col
        linear += self._tables.offset.take(texture)
        index, step = self._index[:, :k]
        np.copyto(index, linear, casting="unsafe")  # whole numbers: exact
        np.copyto(step, width, casting="unsafe")  # from the right neighbour to the lower one
        corners = self._corners[:, :k]
        for corner in range(4):
            if corner:
                index += step if corner == 2 else 1
            for c in range(3):
                np.take(self._tables.pool[c], index, out=corners[3 * corner + c], mode="clip")
        return corners


def _texel_coordinate(
    a: np.ndarray, b: np.ndarray, rows: np.ndarray, *, out: np.ndarray, tmp: np.ndarray
) -> None:
    """``rows[0] + a rows[1] + b rows[2]`` into `out`."""
    np.multiply(a, rows[1], out=out)
    out += rows[0]
    np.multiply(b, rows[2], out=tmp)
    out += tmp


def _split_wrap(coordinate: np.ndarray, size: np.ndarray, *, whole: np.ndarray, tmp: np.ndarray) -> None:
    """Split `coordinate` into its floor, wrapped to ``0 .. size - 1`` into `whole`, and its fraction (in
    place). The wrap is ``whole mod size`` in float32, exact below 2**24 and faster than integer modulo."""
    np.floor(coordinate, out=whole)
    coordinate -= whole
    np.divide(whole, size, out=tmp)
    np.floor(tmp, out=tmp)
    tmp *= size
    whole -= tmp


def _blend(
    corners: np.ndarray, fx: np.ndarray, fy: np.ndarray, *, out: np.ndarray, scratch: np.ndarray
) -> None:
    """Bilinear blend of the ``(12, K)`` corner rows ``3 corner + channel`` (corners: the texel, its right,
    lower and lower-right neighbour) with column and row fractions `fx`, `fy` into the
    ``(3, K)`` channels `out`, using seven ``(K,)`` rows of `scratch`."""
    gx, gy, tmp, *weights = scratch[:7]
    np.subtract(np.float32(1.0), fx, out=gx)
    np.subtract(np.float32(1.0), fy, out=gy)
    for weight, (first, second) in zip(weights, ((gx, gy), (fx, gy), (gx, fy), (fx, fy)), strict=True):
        np.multiply(first, second, out=weight)
    for c in range(3):
        np.multiply(corners[c], weights[0], out=out[c])
        for corner in range(1, 4):
            np.multiply(corners[3 * corner + c], weights[corner], out=tmp)
            out[c] += tmp


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


@dataclass(frozen=True)
class _BodyShape:
    """A shape of moving bodies: its shape in the caster, its faces' unit normals (in its own frame), its
    first row in the renderer's per-face tables and how many bodies of it those rows hold."""

    caster_shape: int
    normals: np.ndarray
    first: int
    slots: int


def _mesh_face_colors(mesh: MeshData) -> np.ndarray:
    """A mesh's per-face sRGB colours ``(F, 3)`` (its own, else a neutral grey)."""
    if mesh.face_colors is not None:
        return np.asarray(mesh.face_colors, dtype=np.float32)[:, :3]
    return np.full((mesh.num_faces, 3), 150.0, dtype=np.float32)
