"""Top-down fields of a scene for scoring trajectories: surface class, obstacles, obstacle distance.

:func:`scene_fields` casts two grids of vertical rays from above the scene (Open3D / Embree):

* through the terrain surfaces alone (classes hidden in the BEV, such as ceilings, left out): the
  class and height of the top surface of each cell, ``terrain``;
* through the objects: the height of each cell's top object face.

A cell is an **obstacle** when its top terrain surface is of a non-navigable class (walls, buildings,
water, ``obstacle``) or an object rises more than :data:`OBSTACLE_MIN_HEIGHT` above the terrain there
(a rug or a doormat does not). ``distance`` is the Euclidean distance transform of the free cells: the
horizontal distance (m) from a cell centre to the nearest obstacle cell. The fields are what the
metrics ADO (distance), NSR (terrain class) and the footprint collision check (distance) read.

Scenes with overhanging geometry (a floor above a floor) are seen from above only: the top surface
wins.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import open3d as o3d
from numpy.typing import ArrayLike
from scipy import ndimage

from navverse.cache import cache_root
from navverse.scene.geometry import MeshData, Scene

__all__ = ["OBSTACLE_MIN_HEIGHT", "SceneFields", "fields_cache_path", "load_scene_fields", "scene_fields"]

OBSTACLE_MIN_HEIGHT = 0.1
"""An object is an obstacle where it rises more than this above the terrain (m)."""
NO_SURFACE = -1
"""``terrain`` where no terrain surface is below the cell."""
_FORMAT = 1


@dataclass(frozen=True, eq=False)
class SceneFields:
    """Rasters over the scene's horizontal bounds; row 0 is the minimum y, column 0 the minimum x.

    Parameters
    ----------
    origin : tuple of float
        World ``(x, y)`` of the grid's minimum corner.
    cell : float
        Cell size (m).
    terrain : ndarray of int16, shape (H, W)
        Index into `class_names` of the top terrain surface, :data:`NO_SURFACE` where none.
    obstacle : ndarray of bool, shape (H, W)
        Obstacle cells.
    distance : ndarray of float32, shape (H, W)
        Distance from each cell centre to the nearest obstacle cell (m; 0 on obstacles).
    class_names : tuple of str
        Terrain class names.
    """

    origin: tuple[float, float]
    cell: float
    terrain: np.ndarray
    obstacle: np.ndarray
    distance: np.ndarray
    class_names: tuple[str, ...]

    def cells(self, xy: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Row and column of world points (..., 2), clipped to the grid."""
        xy = np.asarray(xy, dtype=np.float64)
        h, w = self.terrain.shape
        col = np.clip(np.floor((xy[..., 0] - self.origin[0]) / self.cell), 0, w - 1).astype(np.intp)
        row = np.clip(np.floor((xy[..., 1] - self.origin[1]) / self.cell), 0, h - 1).astype(np.intp)
        return row, col

    def distance_at(self, xy: ArrayLike) -> np.ndarray:
        """Distance to the nearest obstacle (m) at world points (..., 2)."""
        row, col = self.cells(xy)
        return self.distance[row, col]

    def terrain_at(self, xy: ArrayLike) -> np.ndarray:
        """Terrain class index at world points (..., 2)."""
        row, col = self.cells(xy)
        return self.terrain[row, col]

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the fields as a compressed ``.npz`` (atomically)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        with open(tmp, "wb") as handle:
            np.savez_compressed(
                handle,
                format=np.int64(_FORMAT),
                origin=np.asarray(self.origin),
                cell=np.float64(self.cell),
                terrain=self.terrain,
                obstacle=self.obstacle,
                distance=self.distance,
                class_names=np.asarray(self.class_names, dtype=str),
            )
        os.replace(tmp, path)
        return path

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> SceneFields | None:
        """Read fields written by :meth:`save`; None if the file is missing, damaged or of another format."""
        try:
            with np.load(path) as data:
                if int(data["format"]) != _FORMAT:
                    return None
                return cls(
                    origin=(float(data["origin"][0]), float(data["origin"][1])),
                    cell=float(data["cell"]),
                    terrain=data["terrain"],
                    obstacle=data["obstacle"],
                    distance=data["distance"],
                    class_names=tuple(str(n) for n in data["class_names"]),
                )
        except (OSError, KeyError, ValueError):
            return None


def _cast_down(
    mesh: MeshData, origin: np.ndarray, shape: tuple[int, int], cell: float, top: float
) -> tuple[np.ndarray, np.ndarray]:
    """Hit height (NaN where none) and face index of vertical rays through the cell centres."""
    rows, cols = shape
    height = np.full(shape, np.nan)
    face = np.full(shape, -1, dtype=np.int64)
    if mesh.num_faces == 0:
        return height, face
    local = np.array([origin[0], origin[1], 0.0])
    caster = o3d.t.geometry.RaycastingScene()
    caster.add_triangles(
        o3d.core.Tensor((mesh.vertices - local).astype(np.float32)),
        o3d.core.Tensor(mesh.faces.astype(np.uint32)),
    )
    gx, gy = np.meshgrid((np.arange(cols) + 0.5) * cell, (np.arange(rows) + 0.5) * cell)
    rays = np.zeros((rows, cols, 6), dtype=np.float32)
    rays[..., 0], rays[..., 1], rays[..., 2], rays[..., 5] = gx, gy, top, -1.0
    hits = caster.cast_rays(o3d.core.Tensor(rays))
    t_hit = hits["t_hit"].numpy()
    hit = np.isfinite(t_hit)
    height[hit] = top - t_hit[hit]
    face[hit] = hits["primitive_ids"].numpy()[hit].astype(np.int64)
    return height, face


def scene_fields(scene: Scene, *, cell: float | None = None) -> SceneFields:
    """Compute the fields of a scene.

    Parameters
    ----------
    scene : Scene
        The scene.
    cell : float, optional
        Cell size (m); by default 0.05 m indoors and 0.1 m elsewhere, coarsened so that the longer
        side has at most 8000 cells.
    """
    ann = scene.annotations
    (x0, y0, _), (x1, y1, z1) = ann.bounds.min, ann.bounds.max
    longer = max(x1 - x0, y1 - y0)
    cell = float(cell) if cell is not None else (0.05 if ann.scene_type == "indoor" else 0.1)
    cell = max(cell, longer / 8000.0)
    shape = (max(1, math.ceil((y1 - y0) / cell - 1e-9)), max(1, math.ceil((x1 - x0) / cell - 1e-9)))
    origin = np.array([x0, y0])
    hidden = [name for name, tc in ann.terrain_classes.items() if not tc.show_in_bev]
    terrain_mesh = scene.world_mesh(include_objects=False, exclude_classes=hidden)
    objects = [o.world_mesh() for o in scene.objects]
    top = z1 + 1.0
    for mesh in (terrain_mesh.mesh, *objects):
        if mesh.num_faces:
            top = max(top, float(mesh.vertices[:, 2].max()) + 1.0)
    ground, face = _cast_down(terrain_mesh.mesh, origin, shape, cell, top)
    terrain = np.full(shape, NO_SURFACE, dtype=np.int16)
    terrain[face >= 0] = terrain_mesh.class_index[face[face >= 0]]
    names = terrain_mesh.class_names
    blocked = np.array([not ann.terrain_classes[n].navigable for n in names] + [False], dtype=bool)
    obstacle = blocked[np.where(terrain >= 0, terrain, len(names))]
    if objects:
        merged = MeshData.concatenate(MeshData(m.vertices, m.faces) for m in objects)
        object_top, _ = _cast_down(merged, origin, shape, cell, top)
        base = np.where(np.isfinite(ground), ground, -np.inf)
        obstacle |= np.isfinite(object_top) & (object_top - base > OBSTACLE_MIN_HEIGHT)
    distance = (
        ndimage.distance_transform_edt(~obstacle).astype(np.float32) * np.float32(cell)
        if obstacle.any()
        else np.full(shape, np.float32(np.hypot(*shape) * cell))
    )
    return SceneFields((float(x0), float(y0)), cell, terrain, obstacle, distance, tuple(names))


def fields_cache_path(scene_dir: str | os.PathLike[str]) -> Path:
    """Where :func:`load_scene_fields` caches a scene's fields: ``$NAVVERSE_CACHE_DIR/fields/<hash>.npz``,
    keyed by the scene's files (default cache ``~/.cache/navverse``)."""
    from navverse.scene.directory import scene_hash

    return cache_root() / "fields" / f"{scene_hash(scene_dir)[:32]}.npz"


def load_scene_fields(scene_dir: str | os.PathLike[str]) -> SceneFields:
    """The fields of a built scene directory, computed once and then read from the cache."""
    from navverse.scene.directory import read_scene

    path = fields_cache_path(scene_dir)
    cached = SceneFields.load(path) if path.is_file() else None
    if cached is not None:
        return cached
    fields = scene_fields(read_scene(Path(scene_dir)))
    fields.save(path)
    return fields
