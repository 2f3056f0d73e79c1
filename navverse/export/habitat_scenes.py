"""A built scene as habitat-sim scene files: GLB geometry, HM3D-style semantics, the ``.navmesh``.

For a scene ``<id>`` the export writes into ``scenes/<id>/``:

- ``<id>.glb`` — every surface and object mesh in the habitat frame (y up, ``(x, z, -y)`` of the
  z-up world), one triangle list with unshared vertices (three per face) carrying the face colours as
  vertex colours (``COLOR_0``). Textures are not exported (textured faces show their face colour).
- ``<id>.semantic.glb`` and ``<id>.semantic.txt`` — HM3D's semantic layout (habitat-sim's
  ``SemanticScene`` for HM3D): the same triangles coloured by object instance, and a text file whose
  first line is ``HM3D Semantic Annotations`` followed by one ``<id>,<RRGGBB>,"<category>",0`` line per
  object. The colour encodes the instance id (``RRGGBB`` = the id as a 24-bit number), terrain faces are
  black (unlabelled), and a storefront's object carries its place category (``clinic``), so PlaceNav
  goals name the category their object has; a storefront without an object of its own (its sign was
  hidden) is listed as ``STOREFRONT_ID_BASE + storefront id`` with no faces.
- ``<id>.navmesh`` — :mod:`navverse.export.habitat_navmesh`.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np

from navverse.export.habitat_navmesh import mset_from_tiles
from navverse.nav.fileformat import read_navmesh
from navverse.scene.colors import default_color
from navverse.scene.geometry import MeshData, Scene
from navverse.scene.semantics import STOREFRONT_ID_BASE, semantic_categories, storefront_objects

__all__ = [
    "SEMANTIC_HEADER",
    "STOREFRONT_ID_BASE",
    "from_habitat",
    "habitat_rotation",
    "habitat_yaw",
    "scene_triangles",
    "semantic_categories",
    "storefront_objects",
    "to_habitat",
    "write_habitat_scene",
    "yaw_facing",
]

SEMANTIC_HEADER = "HM3D Semantic Annotations"


def to_habitat(points: np.ndarray) -> np.ndarray:
    """Points ``(..., 3)`` of the z-up world in the habitat frame: ``(x, y, z) -> (x, z, -y)``."""
    p = np.asarray(points, dtype=np.float64)
    return np.stack([p[..., 0], p[..., 2], -p[..., 1]], axis=-1)


def from_habitat(points: np.ndarray) -> np.ndarray:
    """Points ``(..., 3)`` of the habitat frame back in the z-up world: ``(x, y, z) -> (x, -z, y)``."""
    p = np.asarray(points, dtype=np.float64)
    return np.stack([p[..., 0], -p[..., 2], p[..., 1]], axis=-1)


def habitat_yaw(rotation: np.ndarray) -> np.ndarray:
    """The z-up yaws (rad, in (-pi, pi]) of habitat ``[x, y, z, w]`` rotations about +y (the inverse of
    :func:`habitat_rotation`)."""
    q = np.asarray(rotation, dtype=np.float64)
    angle = 2.0 * np.arctan2(q[..., 1], q[..., 3]) + np.pi / 2
    return np.angle(np.exp(1j * angle))


def habitat_rotation(yaw: np.ndarray | float) -> np.ndarray:
    """habitat ``[x, y, z, w]`` agent rotations of z-up yaws (rad, 0 along +x): about habitat +y by
    ``yaw - pi/2``, so the agent's forward (-z in its own frame) points along the yaw's heading."""
    half = (np.asarray(yaw, dtype=np.float64) - np.pi / 2) / 2
    zero = np.zeros_like(half)
    return np.stack([zero, np.sin(half), zero, np.cos(half)], axis=-1)


def _face_colors(mesh: MeshData, name: str) -> np.ndarray:
    if mesh.face_colors is not None:
        return np.asarray(mesh.face_colors, dtype=np.uint8)
    return np.tile(np.array(default_color(name), dtype=np.uint8), (mesh.num_faces, 1))


def scene_triangles(scene: Scene) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The scene's triangles in the world frame: corners ``(M, 3, 3)``, face colours ``(M, 3)`` uint8
    and the object id of each face ``(M,)`` (0 for terrain surfaces); surfaces first, then objects."""
    parts = [(s.mesh, _face_colors(s.mesh, s.terrain_class), 0) for s in scene.surfaces]
    for obj in scene.objects:
        mesh = obj.world_mesh()
        parts.append((mesh, _face_colors(mesh, obj.annotation.category), obj.annotation.id))
    if not parts:
        return np.zeros((0, 3, 3)), np.zeros((0, 3), np.uint8), np.zeros(0, np.int64)
    corners = np.concatenate([m.vertices[m.faces] for m, _, _ in parts])
    colors = np.concatenate([c for _, c, _ in parts])
    ids = np.concatenate([np.full(m.num_faces, i, np.int64) for m, _, i in parts])
    return corners, colors, ids


def _glb(corners: np.ndarray, colors: np.ndarray) -> bytes:
    """A GLB of unshared-vertex triangles (habitat frame) with per-vertex RGBA colours."""
    import trimesh

    vertices = to_habitat(corners.reshape(-1, 3))
    faces = np.arange(len(vertices), dtype=np.int64).reshape(-1, 3)
    rgba = np.concatenate([colors, np.full((len(colors), 1), 255, np.uint8)], axis=1)
    mesh = trimesh.Trimesh(vertices, faces, vertex_colors=np.repeat(rgba, 3, axis=0), process=False)
    return mesh.export(file_type="glb")


def id_colors(ids: np.ndarray) -> np.ndarray:
    """The semantic colour of object ids ``(M,)``: the id as a 24-bit ``RRGGBB`` number (0: black)."""
    ids = np.asarray(ids, dtype=np.int64)
    return np.stack([(ids >> 16) & 255, (ids >> 8) & 255, ids & 255], axis=-1).astype(np.uint8)


def semantic_text(categories: Mapping[int, str]) -> str:
    """The ``.semantic.txt`` lines of objects by id."""
    lines = [SEMANTIC_HEADER]
    for obj_id, category in sorted(categories.items()):
        if obj_id >= 1 << 24:
            raise ValueError(f"object id {obj_id} does not fit a 24-bit semantic colour")
        r, g, b = id_colors(np.array([obj_id]))[0]
        name = category.replace('"', "'")
        lines.append(f'{obj_id},{r:02X}{g:02X}{b:02X},"{name}",0')
    return "\n".join(lines) + "\n"


def write_habitat_scene(scene: Scene, navmesh: Path, out_dir: Path) -> dict[str, int]:
    """Write ``<id>.glb``, ``<id>.semantic.glb``, ``<id>.semantic.txt`` and ``<id>.navmesh`` of a scene.

    Parameters
    ----------
    scene : Scene
        The scene read from its directory.
    navmesh : Path
        Its ``navmesh.bin``.
    out_dir : Path
        An existing directory (inside the export's temporary directory).

    Returns
    -------
    dict of str to int
        ``vertices`` and ``faces`` of the GLB, ``objects`` in the semantic file.
    """
    scene_id = scene.scene_id
    corners, colors, ids = scene_triangles(scene)
    (out_dir / f"{scene_id}.glb").write_bytes(_glb(corners, colors))
    (out_dir / f"{scene_id}.semantic.glb").write_bytes(_glb(corners, id_colors(ids)))
    categories = semantic_categories(scene.annotations)
    (out_dir / f"{scene_id}.semantic.txt").write_text(semantic_text(categories), encoding="utf-8")
    _, tiles = read_navmesh(navmesh.read_bytes(), source=str(navmesh))
    (out_dir / f"{scene_id}.navmesh").write_bytes(mset_from_tiles(tiles, source=str(navmesh)))
    return {"vertices": 3 * len(corners), "faces": len(corners), "objects": len(categories)}


def yaw_facing(points: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The z-up yaw (rad) from each of ``points`` ``(N, 3)`` towards ``target`` ``(3,)``."""
    d = np.asarray(target, dtype=np.float64)[:2] - np.asarray(points, dtype=np.float64)[:, :2]
    return np.arctan2(d[:, 1], d[:, 0]) if len(d) else np.zeros(0)
