"""In-memory scene: triangle meshes, terrain surfaces, objects and their annotations.

A :class:`Scene` is what scene stages produce and what :mod:`navverse.scene.usd` writes. Shapes and
indices are checked when objects are built; such errors are programming errors and raise
``ValueError``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from navverse.scene.annotations import ObjectAnnotation, SceneAnnotations
from navverse.scene.naming import is_identifier

__all__ = [
    "VERTEX_GRID",
    "LabeledMesh",
    "MeshData",
    "Scene",
    "SceneObject",
    "Surface",
    "Texture",
    "apply_linear",
    "merge_textures",
    "snap_to_grid",
    "yaw_matrix",
]

VERTEX_GRID = 2.0**-20
"""Step (m, about 1 µm) of the grid generated vertices are snapped to (:func:`snap_to_grid`)."""


def snap_to_grid(values: ArrayLike, step: float = VERTEX_GRID) -> np.ndarray:
    """`values` rounded to the nearest multiple of `step` (a power of two: the rounding is exact).

    Generated geometry passes through functions whose last bit depends on the machine: numpy's
    AVX-512 versions of ``exp``/``log``/``arctan2``/``power``, and OpenBLAS's kernels behind ``@`` and
    ``dot``, which differ between processors. Snapping the vertices of generated meshes (and the
    points whose convex hull or boolean is taken) to this grid makes those last-bit differences vanish,
    so a scene is the same bytes on every x86-64 machine; a difference survives only if a value lies
    within a few units in the last place of a half-step, about one value in 10^9. A zero comes out
    as 0.0 whatever its sign was.
    """
    grid = np.asarray(values, dtype=np.float64) / step
    return np.round(grid) * step + 0.0  # + 0.0: -0.0 (a tiny negative rounded) becomes 0.0


def apply_linear(points: ArrayLike, matrix: ArrayLike) -> np.ndarray:
    """``points @ matrix.T`` for points (..., d) and a (k, d) matrix, with the same bits on every machine.

    ``@`` goes to the BLAS library, whose kernels (and their use of fused multiply-adds) differ between
    processors; this sums the d products in a fixed order with numpy's element-wise arithmetic.
    """
    p = np.asarray(points, dtype=np.float64)
    m = np.asarray(matrix, dtype=np.float64)
    total = p[..., 0:1] * m[:, 0]
    for k in range(1, m.shape[1]):
        total = total + p[..., k : k + 1] * m[:, k]
    return total


def unit_face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit normals ``(F, 3)`` of triangles (counter-clockwise winding); zero for degenerate ones."""
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return np.divide(normals, length, out=np.zeros_like(normals), where=length > 0)


def yaw_matrix(yaw: float) -> np.ndarray:
    """Return the 3x3 rotation about +z by `yaw` radians."""
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def merge_textures(meshes: Sequence[MeshData]) -> tuple[np.ndarray, np.ndarray, tuple[Texture, ...]]:
    """The textures of meshes taken in order as one set: textures shared by name, faces re-indexed.

    Returns
    -------
    face_uvs : ndarray of float32, shape (F, 3, 2)
        Every face's corner UVs (zeros for untextured faces), meshes in order.
    face_texture : ndarray of int32, shape (F,)
        Index into `textures` of every face's texture, -1 for untextured faces.
    textures : tuple of Texture
        Each name once, in order of first use.

    Raises
    ------
    ValueError
        If two different images share a name.
    """
    textures: dict[str, Texture] = {}
    uvs, index = [], []
    for mesh in meshes:
        if mesh.face_texture is None:
            uvs.append(np.zeros((mesh.num_faces, 3, 2), np.float32))
            index.append(np.full(mesh.num_faces, -1, np.int32))
            continue
        remap = []
        for texture in mesh.textures:
            known = textures.setdefault(texture.name, texture)
            if not known.same_image(texture):
                raise ValueError(f"two different images are both named {texture.name!r}")
            remap.append(list(textures).index(texture.name))
        table = np.array([*remap, -1], dtype=np.int32)  # -1 indexes the last entry: untextured
        uvs.append(mesh.face_uvs)
        index.append(table[mesh.face_texture])
    if not uvs:
        return np.zeros((0, 3, 2), np.float32), np.zeros(0, np.int32), ()
    return np.concatenate(uvs), np.concatenate(index), tuple(textures.values())


def _frozen(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class Texture:
    """An sRGB image that textured faces show through their UV coordinates.

    Parameters
    ----------
    name : str
        A USD identifier, unique within a scene: the image is written as ``textures/<name>.png``
        beside ``scene.usdc``. Two textures of one scene with the same name must hold the same image.
    image : ndarray of uint8, shape (H, W, 3)
        Row 0 is the top of the image (``v = 1``), column 0 its left edge (``u = 0``).
    """

    name: str
    image: np.ndarray

    def __post_init__(self) -> None:
        if not is_identifier(self.name):
            raise ValueError(f"texture name {self.name!r} is not a valid USD identifier")
        image = np.asarray(self.image)
        if image.ndim != 3 or image.shape[2] != 3 or image.shape[0] < 1 or image.shape[1] < 1:
            raise ValueError(f"texture {self.name!r}: image must have shape (H, W, 3), got {image.shape}")
        if image.dtype != np.uint8:
            raise ValueError(f"texture {self.name!r}: image must be uint8, got {image.dtype}")
        object.__setattr__(self, "image", _frozen(np.array(image, dtype=np.uint8)))

    def same_image(self, other: Texture) -> bool:
        """Whether ``other`` holds the same pixels."""
        return self.image is other.image or (
            self.image.shape == other.image.shape and bool(np.array_equal(self.image, other.image))
        )


@dataclass(frozen=True, eq=False)
class MeshData:
    """A triangle mesh.

    Parameters
    ----------
    vertices : ndarray, shape (N, 3)
        Vertex positions in meters; stored as float64.
    faces : ndarray, shape (M, 3)
        Vertex indices per triangle (counter-clockwise seen from outside); stored as int64.
    face_colors : ndarray, shape (M, 3), optional
        sRGB colour per face, 0..255; stored as uint8. A textured face keeps its colour too (what
        viewers without textures show).
    face_uvs : ndarray, shape (M, 3, 2), optional
        Texture coordinates of each face's three corners (``u`` right, ``v`` up, 0..1 over the
        image; values outside repeat it); stored as float32. Given with ``face_texture``.
    face_texture : ndarray, shape (M,), optional
        Index into ``textures`` of each face's texture, ``-1`` for an untextured face; stored as
        int16.
    textures : tuple of Texture
        The textures the faces index.

    Notes
    -----
    The arrays are copied and made read-only, so a mesh cannot change after it is built.
    """

    vertices: np.ndarray
    faces: np.ndarray
    face_colors: np.ndarray | None = None
    face_uvs: np.ndarray | None = None
    face_texture: np.ndarray | None = None
    textures: tuple[Texture, ...] = ()

    def __post_init__(self) -> None:
        vertices = np.array(self.vertices, dtype=np.float64)
        if vertices.size == 0:
            vertices = vertices.reshape(0, 3)
        if vertices.ndim != 2 or vertices.shape[1] != 3:
            raise ValueError(f"vertices must have shape (N, 3), got {vertices.shape}")
        if not np.isfinite(vertices).all():
            raise ValueError("vertices must be finite")
        faces_in = np.asarray(self.faces)
        if faces_in.size == 0:
            faces_in = faces_in.reshape(0, 3).astype(np.int64)
        if not np.issubdtype(faces_in.dtype, np.integer):
            raise ValueError(f"faces must hold integers, got dtype {faces_in.dtype}")
        faces = np.array(faces_in, dtype=np.int64)
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise ValueError(f"faces must have shape (M, 3), got {faces.shape}")
        if faces.size and (faces.min() < 0 or faces.max() >= len(vertices)):
            raise ValueError(
                f"face indices must be in [0, {len(vertices)}), got [{faces.min()}, {faces.max()}]"
            )
        object.__setattr__(self, "vertices", _frozen(vertices))
        object.__setattr__(self, "faces", _frozen(faces))
        if self.face_colors is not None:
            colors_in = np.asarray(self.face_colors)
            if colors_in.shape != faces.shape:
                raise ValueError(f"face_colors must have shape {faces.shape}, got {colors_in.shape}")
            if colors_in.size and (
                not np.issubdtype(colors_in.dtype, np.integer) or colors_in.min() < 0 or colors_in.max() > 255
            ):
                raise ValueError("face_colors must hold integers in 0..255")
            object.__setattr__(self, "face_colors", _frozen(np.array(colors_in, dtype=np.uint8)))
        self._check_textures(len(faces))

    def _check_textures(self, num_faces: int) -> None:
        if (self.face_uvs is None) != (self.face_texture is None):
            raise ValueError("face_uvs and face_texture come together: give both or neither")
        object.__setattr__(self, "textures", tuple(self.textures))
        if self.face_uvs is None:
            if self.textures:
                raise ValueError("textures need face_uvs and face_texture")
            return
        uvs = np.array(self.face_uvs, dtype=np.float32)
        if uvs.shape != (num_faces, 3, 2):
            raise ValueError(f"face_uvs must have shape ({num_faces}, 3, 2), got {uvs.shape}")
        if not np.isfinite(uvs).all():
            raise ValueError("face_uvs must be finite")
        index = np.asarray(self.face_texture)
        if index.shape != (num_faces,) or (index.size and not np.issubdtype(index.dtype, np.integer)):
            raise ValueError(f"face_texture must hold {num_faces} integers, got shape {index.shape}")
        if index.size and (index.min() < -1 or index.max() >= len(self.textures)):
            raise ValueError(
                f"face_texture must be in [-1, {len(self.textures)}), got [{index.min()}, {index.max()}]"
            )
        names = [t.name for t in self.textures]
        if len(set(names)) != len(names):
            raise ValueError(f"textures of one mesh need distinct names, got {names}")
        object.__setattr__(self, "face_uvs", _frozen(uvs))
        object.__setattr__(self, "face_texture", _frozen(np.array(index, dtype=np.int16)))

    @property
    def textured(self) -> bool:
        """Whether any face shows a texture."""
        return self.face_texture is not None and bool((self.face_texture >= 0).any())

    @property
    def num_vertices(self) -> int:
        """Number of vertices."""
        return int(self.vertices.shape[0])

    @property
    def num_faces(self) -> int:
        """Number of triangles."""
        return int(self.faces.shape[0])

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the axis-aligned bounds ``(min_xyz, max_xyz)`` of the vertices.

        Raises
        ------
        ValueError
            If the mesh has no vertices.
        """
        if self.num_vertices == 0:
            raise ValueError("an empty mesh has no bounds")
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def transformed(self, translation: ArrayLike, yaw: float = 0.0) -> MeshData:
        """Return the mesh rotated by `yaw` about +z, then translated.

        Parameters
        ----------
        translation : array_like, shape (3,)
            Offset added after the rotation.
        yaw : float
            Rotation about +z in radians.

        Returns
        -------
        MeshData
            ``Rz(yaw) @ v + translation`` for every vertex ``v``; faces and colours unchanged.
        """
        offset = np.asarray(translation, dtype=np.float64).reshape(3)
        vertices = apply_linear(self.vertices, yaw_matrix(yaw)) + offset
        return MeshData(
            vertices, self.faces, self.face_colors, self.face_uvs, self.face_texture, self.textures
        )

    def face_subset(self, keep: ArrayLike) -> MeshData:
        """The mesh with only the faces `keep` selects (a boolean mask or indices), and their vertices.

        Colours, UVs and texture indices follow their faces; vertices no kept face uses are dropped.
        """
        kept = self.faces[np.asarray(keep)]
        used, faces = np.unique(kept, return_inverse=True)
        textured = self.face_texture is not None
        return MeshData(
            self.vertices[used],
            faces.reshape(-1, 3),
            None if self.face_colors is None else self.face_colors[np.asarray(keep)],
            self.face_uvs[np.asarray(keep)] if textured else None,
            self.face_texture[np.asarray(keep)] if textured else None,
            self.textures if textured else (),
        )

    @staticmethod
    def concatenate(meshes: Iterable[MeshData]) -> MeshData:
        """Join meshes into one, re-indexing faces.

        Face colours are kept if every mesh has them (or none has); mixing raises ``ValueError``.
        Textures are merged by name (one name must hold one image, else ``ValueError``); faces of
        meshes without textures are untextured. No meshes give an empty mesh.
        """
        meshes = list(meshes)
        if not meshes:
            return MeshData(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
        with_colors = [m.face_colors is not None for m in meshes]
        if any(with_colors) and not all(with_colors):
            raise ValueError(
                "cannot concatenate meshes with and without face_colors; give every mesh colours"
            )
        offsets = np.cumsum([0] + [m.num_vertices for m in meshes[:-1]])
        vertices = np.concatenate([m.vertices for m in meshes])
        faces = np.concatenate([m.faces + off for m, off in zip(meshes, offsets, strict=True)])
        colors = np.concatenate([m.face_colors for m in meshes]) if all(with_colors) else None
        if not any(m.textures for m in meshes):
            return MeshData(vertices, faces, colors)
        uvs, index, textures = merge_textures(meshes)
        return MeshData(vertices, faces, colors, uvs, index.astype(np.int16), textures)

    @classmethod
    def box(cls, size: ArrayLike, *, center: ArrayLike = (0.0, 0.0, 0.0)) -> MeshData:
        """Return an axis-aligned box with outward-facing triangles.

        Parameters
        ----------
        size : array_like, shape (3,)
            Extent along x, y, z; all > 0.
        center : array_like, shape (3,)
            Centre of the box.

        Returns
        -------
        MeshData
            8 vertices, 12 triangles.
        """
        half = 0.5 * np.asarray(size, dtype=np.float64).reshape(3)
        if (half <= 0).any():
            raise ValueError(f"box size must be > 0 on every axis, got {2 * half}")
        corners = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], dtype=np.float64)
        vertices = corners * half + np.asarray(center, dtype=np.float64).reshape(3)
        faces = np.array(
            [
                [0, 2, 1], [1, 2, 3],  # bottom (-z)
                [4, 5, 6], [5, 7, 6],  # top (+z)
                [0, 1, 4], [1, 5, 4],  # front (-y)
                [2, 6, 3], [3, 6, 7],  # back (+y)
                [0, 4, 2], [2, 4, 6],  # left (-x)
                [1, 3, 5], [3, 7, 5],  # right (+x)
            ],
            dtype=np.int64,
        )  # fmt: skip
        return cls(vertices, faces)


@dataclass(frozen=True, eq=False)
class Surface:
    """Static geometry of one terrain class, e.g. the floor of a room or a stretch of road.

    Parameters
    ----------
    name : str
        Prim name under ``/World/Terrain``; must be a USD identifier (see
        :func:`navverse.scene.naming.sanitize_identifier`) and unique within the scene.
    terrain_class : str
        Key into ``SceneAnnotations.terrain_classes``.
    mesh : MeshData
        Geometry in world coordinates.
    """

    name: str
    terrain_class: str
    mesh: MeshData

    def __post_init__(self) -> None:
        if not is_identifier(self.name):
            raise ValueError(
                f"surface name {self.name!r} is not a valid USD identifier; use sanitize_identifier()"
            )
        if not self.terrain_class:
            raise ValueError(f"surface {self.name!r} needs a terrain class")


@dataclass(frozen=True, eq=False)
class SceneObject:
    """An object instance: its annotation and its mesh in the object's local frame.

    The world position of a local vertex ``v`` is ``Rz(annotation.yaw) @ v + annotation.center``.
    """

    annotation: ObjectAnnotation
    mesh: MeshData

    def world_mesh(self) -> MeshData:
        """Return the mesh placed in the world frame."""
        return self.mesh.transformed(self.annotation.center, self.annotation.yaw)


@dataclass(frozen=True, eq=False)
class LabeledMesh:
    """A world-frame mesh with per-face labels.

    Parameters
    ----------
    mesh : MeshData
        All selected geometry in world coordinates.
    class_index : ndarray of int16, shape (M,)
        Index into `class_names` for faces of terrain surfaces; ``-1`` for object faces.
    instance_id : ndarray of int32, shape (M,)
        Object instance id for object faces; ``0`` for terrain surfaces.
    class_names : tuple of str
        Terrain class names, in the order of ``SceneAnnotations.terrain_classes``.
    """

    mesh: MeshData
    class_index: np.ndarray
    instance_id: np.ndarray
    class_names: tuple[str, ...]

    def __post_init__(self) -> None:
        n = self.mesh.num_faces
        if self.class_index.shape != (n,) or self.instance_id.shape != (n,):
            raise ValueError(f"class_index and instance_id must have shape ({n},)")

    def class_mask(self, name: str) -> np.ndarray:
        """Return a boolean mask of the faces of terrain class `name` (all False if absent)."""
        if name not in self.class_names:
            return np.zeros(self.mesh.num_faces, dtype=bool)
        return self.class_index == self.class_names.index(name)

    @property
    def object_mask(self) -> np.ndarray:
        """Boolean mask of faces that belong to objects."""
        return self.instance_id > 0


@dataclass(frozen=True, eq=False)
class Scene:
    """A complete scene in memory: annotations, terrain surfaces and objects.

    Parameters
    ----------
    annotations : SceneAnnotations
        The contents of ``scene.json``.
    surfaces : tuple of Surface
        Static terrain geometry; every ``terrain_class`` must be in ``annotations.terrain_classes``
        and names must be unique.
    objects : tuple of SceneObject
        One per entry of ``annotations.objects``, in the same order and with equal annotations.
    """

    annotations: SceneAnnotations
    surfaces: tuple[Surface, ...] = field(default=())
    objects: tuple[SceneObject, ...] = field(default=())

    def __post_init__(self) -> None:
        object.__setattr__(self, "surfaces", tuple(self.surfaces))
        object.__setattr__(self, "objects", tuple(self.objects))
        known = self.annotations.terrain_classes
        names = [s.name for s in self.surfaces]
        if len(set(names)) != len(names):
            repeated = sorted({n for n in names if names.count(n) > 1})
            raise ValueError(f"surface names must be unique; repeated: {repeated}")
        for surface in self.surfaces:
            if surface.terrain_class not in known:
                raise ValueError(
                    f"surface {surface.name!r} has terrain class {surface.terrain_class!r}, which is not in "
                    f"the annotations' terrain classes ({', '.join(known)})"
                )
        expected = self.annotations.objects
        if len(self.objects) != len(expected) or any(
            obj.annotation != ann for obj, ann in zip(self.objects, expected, strict=False)
        ):
            raise ValueError("scene objects must carry exactly annotations.objects, in the same order")

    @property
    def scene_id(self) -> str:
        """The scene's id."""
        return self.annotations.scene_id

    def world_mesh(self, *, include_objects: bool = True, exclude_classes: Sequence[str] = ()) -> LabeledMesh:
        """Merge the scene's geometry into one labelled world-frame mesh.

        Parameters
        ----------
        include_objects : bool
            Whether object meshes are included.
        exclude_classes : sequence of str
            Terrain classes to leave out (e.g. ``("ceiling",)``); names absent from the scene are
            ignored, so one list can serve every scene.

        Returns
        -------
        LabeledMesh
            Surfaces first (in order), then objects, with per-face class index and instance id.
            Face colours are not carried over; the labels say what each face is.
        """
        class_names = tuple(self.annotations.terrain_classes)
        excluded = set(exclude_classes)
        meshes: list[MeshData] = []
        class_index: list[np.ndarray] = []
        instance_id: list[np.ndarray] = []
        for surface in self.surfaces:
            if surface.terrain_class in excluded:
                continue
            meshes.append(surface.mesh)
            class_index.append(
                np.full(surface.mesh.num_faces, class_names.index(surface.terrain_class), np.int16)
            )
            instance_id.append(np.zeros(surface.mesh.num_faces, np.int32))
        if include_objects:
            for obj in self.objects:
                meshes.append(obj.world_mesh())
                class_index.append(np.full(obj.mesh.num_faces, -1, np.int16))
                instance_id.append(np.full(obj.mesh.num_faces, obj.annotation.id, np.int32))
        mesh = MeshData.concatenate(MeshData(m.vertices, m.faces) for m in meshes)
        return LabeledMesh(
            mesh=mesh,
            class_index=np.concatenate(class_index) if class_index else np.zeros(0, np.int16),
            instance_id=np.concatenate(instance_id) if instance_id else np.zeros(0, np.int32),
            class_names=class_names,
        )
