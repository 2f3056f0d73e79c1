"""Top-down fields of a scene for scoring trajectories: surface class, obstacles, obstacle distance, indoor.

The fields describe what a ground robot meets: the surface it walks on and the geometry its body can
hit. :func:`scene_fields` casts batches of vertical rays through the cell centres (Open3D / Embree):

1. **Walkable ground.** Down from above the scene through the navigable terrain alone (classes hidden
   in the BEV, such as ceilings, always left out): the height and class of the top walkable surface.
2. **Body band.** Down from :data:`BODY_HEIGHT` above that ground through everything else (the visible
   non-navigable terrain and the objects). A cell is an **obstacle** when

   * the first hit lies more than :data:`OBSTACLE_MIN_HEIGHT` above the ground: something occupies the
     band between those two heights (a table top, a chair seat, a low wall; a rug or a doormat does
     not count);
   * the first hit, wherever it is, is a back face (its normal points along the ray): the ray started
     inside a solid that fills the band, such as a wall or a shelf taller than the band. Wall bottoms
     coincide with the floor's top; leaving the walkable ground out of this cast keeps the floor from
     hiding them;
   * the first hit is a front face of non-navigable terrain at ground level (water, a hole's cover).

   Geometry wholly above the band is not an obstacle: the wall above a door opening (its header), a
   pendant lamp, a shelf mounted on a wall above the body.
3. **No walkable ground.** A cell is an obstacle when non-navigable terrain or an object is above it,
   and free when nothing is (the void beyond the scene).

``terrain`` is the class of the walkable ground, so the surface read in a doorway is the floor; where the
obstacle is terrain (inside a wall, a low wall's top, water at ground level) it is that terrain's class,
and where there is no walkable ground it is the class of the top visible terrain surface
(:data:`NO_SURFACE` when there is none). Only the top walkable surface counts: a floor above a floor is
seen from above. ``distance`` is the Euclidean distance transform of the free cells: the horizontal
distance (m) from a cell centre to the nearest obstacle cell. The fields are what the metrics ADO
(distance), NSR (terrain class) and the footprint collision check (distance) read. ``indoor`` marks the
cells whose centre lies inside the union of the scene's indoor region (the footprints of the buildings
marked ``indoor``; all False when there are none): the indoor-to-outdoor transition measures read it.

Solids are assumed closed (the toolkit's walls and most assets are): the inside test reads the face
by which a ray leaves the solid below the band, so a solid without a bottom face and with no face in
the band is missed (a few cells inside some open-mesh furniture). Thin vertical surfaces (a wall
modelled as a single plane) are invisible to vertical rays.
"""

from __future__ import annotations

import math
import os
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage

from navverse.cache import cache_root
from navverse.files import atomic_write
from navverse.scene.geometry import LabeledMesh, MeshData, Scene
from navverse.scene_types import scene_profile

__all__ = [
    "BODY_HEIGHT",
    "OBSTACLE_MIN_HEIGHT",
    "SceneFields",
    "fields_cache_path",
    "indoor_raster",
    "load_scene_fields",
    "scene_fields",
]

OBSTACLE_MIN_HEIGHT = 0.1
"""Bottom of the body band (m above the walkable ground): lower geometry (a rug, a doormat, a door sill)
is stepped or driven over."""
BODY_HEIGHT = 1.0
"""Top of the body band (m above the walkable ground): geometry between :data:`OBSTACLE_MIN_HEIGHT` and
this height is what a ground robot's body can hit. The embodiments' envelopes are 0.65 m (Spot, whose
trunk top stands at ~0.7 m, more with a payload) and 0.42 m (TurtleBot) tall; 1 m covers both with a
margin, keeps tables (0.75 m) and counters (0.9 m) obstacles, and leaves door headers (2.1 m and up),
pendant lamps and shelves mounted on a wall above it free. One height serves every embodiment: the
fields are cached per scene."""
NO_SURFACE = -1
"""``terrain`` where no terrain surface is below the cell."""
_GROUND_TOLERANCE = 1e-3
"""A non-navigable terrain face at most this far below the walkable ground is at ground level (m)."""
RAYS_PER_BAND = 1 << 20
"""Cells cast at a time by :func:`scene_fields` (about 100 MB of working memory)."""

_FORMAT = 3
"""Version of the cached ``.npz``; a file of another version is recomputed (2 added ``indoor``; 3: the
obstacles are the body band above the walkable ground, no longer the top surfaces)."""


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
        Index into `class_names` of the walkable surface (or the obstacle's terrain class, or the top
        terrain surface where nothing is walkable), :data:`NO_SURFACE` where there is no surface.
    obstacle : ndarray of bool, shape (H, W)
        Obstacle cells.
    distance : ndarray of float32, shape (H, W)
        Distance from each cell centre to the nearest obstacle cell (m; 0 on obstacles).
    class_names : tuple of str
        Terrain class names.
    indoor : ndarray of bool, shape (H, W), optional
        Cells inside the scene's indoor region; all False by default (no indoor region).
    """

    origin: tuple[float, float]
    cell: float
    terrain: np.ndarray
    obstacle: np.ndarray
    distance: np.ndarray
    class_names: tuple[str, ...]
    indoor: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.indoor is None:
            object.__setattr__(self, "indoor", np.zeros(self.terrain.shape, dtype=bool))
        elif self.indoor.shape != self.terrain.shape:
            raise ValueError(f"indoor raster {self.indoor.shape} differs from terrain {self.terrain.shape}")

    @property
    def has_indoor(self) -> bool:
        """Whether the scene has an indoor region."""
        return bool(self.indoor.any())

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

    def indoor_at(self, xy: ArrayLike) -> np.ndarray:
        """Whether world points (..., 2) are inside the indoor region (False outside the grid)."""
        xy = np.asarray(xy, dtype=np.float64)
        h, w = self.terrain.shape
        col = np.floor((xy[..., 0] - self.origin[0]) / self.cell)
        row = np.floor((xy[..., 1] - self.origin[1]) / self.cell)
        on_grid = (col >= 0) & (col < w) & (row >= 0) & (row < h)
        r, c = self.cells(xy)
        return self.indoor[r, c] & on_grid

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the fields as a compressed ``.npz`` (atomically)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_write(path) as handle:
            np.savez_compressed(
                handle,
                format=np.int64(_FORMAT),
                origin=np.asarray(self.origin),
                cell=np.float64(self.cell),
                terrain=self.terrain,
                obstacle=self.obstacle,
                distance=self.distance,
                class_names=np.asarray(self.class_names, dtype=str),
                indoor=self.indoor,
            )
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
                    indoor=data["indoor"].astype(bool),
                )
        except (OSError, zipfile.BadZipFile, KeyError, ValueError):
            return None


@dataclass(frozen=True)
class _Hits:
    """First hits of a batch of downward rays; ``part`` is -1 where a ray hit nothing."""

    height: np.ndarray
    part: np.ndarray
    face: np.ndarray
    exits: np.ndarray
    """Whether the hit face is a back face (its normal points down, along the ray): the ray was inside a
    solid and leaves it there."""


class _Caster:
    """Downward rays through a set of meshes (``parts``), in coordinates relative to the grid origin."""

    def __init__(self, parts: Sequence[MeshData], origin: np.ndarray) -> None:
        import open3d as o3d  # here: reading cached fields (scoring) needs no ray caster

        local = np.array([origin[0], origin[1], 0.0])
        self._scene = o3d.t.geometry.RaycastingScene()
        self._part: dict[int, int] = {}
        for index, mesh in enumerate(parts):
            if mesh.num_faces:
                geometry = self._scene.add_triangles(
                    o3d.core.Tensor((mesh.vertices - local).astype(np.float32)),
                    o3d.core.Tensor(mesh.faces.astype(np.uint32)),
                )
                self._part[int(geometry)] = index

    def cast_down(self, xy: np.ndarray, z: np.ndarray) -> _Hits:
        """First hits of rays going down from ``(x, y, z)``; `xy` (N, 2) relative to the grid origin."""
        count = len(z)
        hits = _Hits(np.full(count, np.nan), np.full(count, -1), np.full(count, -1), np.zeros(count, bool))
        if not self._part or count == 0:
            return hits
        rays = np.zeros((count, 6), dtype=np.float32)
        rays[:, :2], rays[:, 2], rays[:, 5] = xy, z, -1.0
        import open3d as o3d

        result = self._scene.cast_rays(o3d.core.Tensor(rays))
        t_hit = result["t_hit"].numpy()
        hit = np.isfinite(t_hit)
        hits.height[hit] = z[hit] - t_hit[hit]
        lookup = np.full(max(self._part) + 1, -1)
        lookup[list(self._part)] = list(self._part.values())
        hits.part[hit] = lookup[result["geometry_ids"].numpy()[hit].astype(np.int64)]
        hits.face[hit] = result["primitive_ids"].numpy()[hit].astype(np.int64)
        hits.exits[hit] = result["primitive_normals"].numpy()[hit, 2] < 0
        return hits


def indoor_raster(
    polygons: Sequence[Sequence[Sequence[float]]], origin: ArrayLike, shape: tuple[int, int], cell: float
) -> np.ndarray:
    """Cells of a grid whose centre lies inside the union of `polygons` (xy vertex lists).

    Parameters
    ----------
    polygons : sequence of polygons
        Each a sequence of ``(x, y)`` vertices (closed implicitly).
    origin : array_like
        World ``(x, y)`` of the grid's minimum corner.
    shape : tuple of int
        ``(rows, cols)``; row 0 is the minimum y.
    cell : float
        Cell size (m).
    """
    from matplotlib.path import Path as PolygonPath

    x0, y0 = (float(v) for v in np.asarray(origin, dtype=np.float64)[:2])
    rows, cols = shape
    inside = np.zeros(shape, dtype=bool)
    for polygon in polygons:
        vertices = np.asarray(polygon, dtype=np.float64)[:, :2]
        # Only the cells under the polygon's bounding box are tested.
        c0 = max(0, math.floor((vertices[:, 0].min() - x0) / cell))
        c1 = min(cols, math.ceil((vertices[:, 0].max() - x0) / cell) + 1)
        r0 = max(0, math.floor((vertices[:, 1].min() - y0) / cell))
        r1 = min(rows, math.ceil((vertices[:, 1].max() - y0) / cell) + 1)
        if c0 >= c1 or r0 >= r1:
            continue
        gx, gy = np.meshgrid(x0 + (np.arange(c0, c1) + 0.5) * cell, y0 + (np.arange(r0, r1) + 0.5) * cell)
        hit = PolygonPath(vertices).contains_points(np.column_stack([gx.ravel(), gy.ravel()]))
        inside[r0:r1, c0:c1] |= hit.reshape(gx.shape)
    return inside


def scene_fields(
    scene: Scene, *, cell: float | None = None, rays_per_band: int = RAYS_PER_BAND
) -> SceneFields:
    """Compute the fields of a scene (see the module's description).

    Parameters
    ----------
    scene : Scene
        The scene.
    cell : float, optional
        Cell size (m); by default the ``field_cell_m`` of the scene type's profile
        (:mod:`navverse.scene_types`: 0.05 m indoors, 0.1 m elsewhere), coarsened so that the longer
        side has at most 8000 cells.
    rays_per_band : int
        About how many cells are cast at a time (in bands of whole rows): bounds the ray-casting
        working memory, not the result.

    Raises
    ------
    ValueError
        If `rays_per_band` is not positive.
    """
    if rays_per_band < 1:
        raise ValueError(f"rays_per_band must be positive, got {rays_per_band}")
    ann = scene.annotations
    (x0, y0, _), (x1, y1, z1) = ann.bounds.min, ann.bounds.max
    longer = max(x1 - x0, y1 - y0)
    cell = float(cell) if cell is not None else scene_profile(ann.scene_type).field_cell_m
    cell = max(cell, longer / 8000.0)
    shape = (max(1, math.ceil((y1 - y0) / cell - 1e-9)), max(1, math.ceil((x1 - x0) / cell - 1e-9)))
    origin = np.array([x0, y0])
    classes = ann.terrain_classes
    names = tuple(classes)
    hidden = [name for name in names if not classes[name].show_in_bev]
    navigable = [name for name in names if classes[name].navigable]
    blocking = [name for name in names if name not in navigable]
    walkable = scene.world_mesh(include_objects=False, exclude_classes=[*hidden, *blocking])
    solid = scene.world_mesh(include_objects=False, exclude_classes=[*hidden, *navigable])
    placed = [o.world_mesh() for o in scene.objects]
    objects = MeshData.concatenate(MeshData(m.vertices, m.faces) for m in placed)
    top = z1 + 1.0
    for mesh in (walkable.mesh, solid.mesh, objects):
        if mesh.num_faces:
            top = max(top, float(mesh.vertices[:, 2].max()) + 1.0)
    casters = _Casters(
        ground=_Caster([walkable.mesh], origin),
        band=_Caster([solid.mesh, objects], origin),
        surface=_Caster([solid.mesh], origin),
    )
    terrain = np.empty(shape, dtype=np.int16)
    obstacle = np.empty(shape, dtype=bool)
    xs = (np.arange(shape[1]) + 0.5) * cell
    rows_per_band = max(1, rays_per_band // shape[1])
    for r0 in range(0, shape[0], rows_per_band):  # each cell's rays are its own: bands change nothing
        r1 = min(shape[0], r0 + rows_per_band)
        gx, gy = np.meshgrid(xs, (np.arange(r0, r1) + 0.5) * cell)
        band_terrain, band_obstacle = _cast_cells(
            casters, np.column_stack([gx.ravel(), gy.ravel()]), top, walkable, solid
        )
        terrain[r0:r1], obstacle[r0:r1] = (
            band_terrain.reshape(-1, shape[1]),
            band_obstacle.reshape(-1, shape[1]),
        )

    distance = (
        _obstacle_distance(obstacle, cell, rows_per_band)
        if obstacle.any()
        else np.full(shape, np.float32(np.hypot(*shape) * cell))
    )
    indoor = indoor_raster(ann.indoor_polygons, origin, shape, cell)
    return SceneFields((float(x0), float(y0)), cell, terrain, obstacle, distance, names, indoor)


@dataclass(frozen=True)
class _Casters:
    """The three ray casters of :func:`scene_fields`: the walkable ground, the body band (part 0 the
    non-navigable terrain, part 1 the objects) and the non-navigable terrain alone."""

    ground: _Caster
    band: _Caster
    surface: _Caster


def _cast_cells(
    casters: _Casters, xy: np.ndarray, top: float, walkable: LabeledMesh, solid: LabeledMesh
) -> tuple[np.ndarray, np.ndarray]:
    """The terrain class and the obstacle flag of the cells centred at `xy` (relative to the grid
    origin), from rays cast down from height `top`."""
    count = len(xy)

    # 1. The walkable ground: the top navigable surface.
    ground_hits = casters.ground.cast_down(xy, np.full(count, top))
    ground = ground_hits.height
    has_ground = np.isfinite(ground)
    terrain = np.full(count, NO_SURFACE, dtype=np.int16)
    terrain[has_ground] = walkable.class_index[ground_hits.face[has_ground]]

    # 2. The body band above the ground, and the columns with no ground, in one batch.
    on, off = np.flatnonzero(has_ground), np.flatnonzero(~has_ground)
    band = casters.band.cast_down(
        np.concatenate([xy[on], xy[off]]), np.concatenate([ground[on] + BODY_HEIGHT, np.full(len(off), top)])
    )
    level, part, exits = band.height[: len(on)], band.part[: len(on)], band.exits[: len(on)]
    above = ground[on] + OBSTACLE_MIN_HEIGHT
    in_band = (part >= 0) & (level > above)
    at_ground = (part == 0) & ~exits & (level >= ground[on] - _GROUND_TOLERANCE)
    obstacle = np.zeros(count, dtype=bool)
    obstacle[on] = in_band | exits | at_ground
    by_terrain = obstacle[on] & (part == 0)
    terrain[on[by_terrain]] = solid.class_index[band.face[: len(on)][by_terrain]]
    obstacle[off] = band.part[len(on) :] >= 0

    # 3. The class where nothing is walkable: the top visible (hence non-navigable) terrain surface.
    if len(off):
        surface = casters.surface.cast_down(xy[off], np.full(len(off), top))
        hit = surface.part >= 0
        terrain[off[hit]] = solid.class_index[surface.face[hit]]
    return terrain, obstacle


def _obstacle_distance(obstacle: np.ndarray, cell: float, rows_per_band: int) -> np.ndarray:
    """The Euclidean distance (m, float32) of every cell to the nearest obstacle cell.

    SciPy's exact transform gives each cell its nearest obstacle; the distances are then taken in bands
    of rows, with the same arithmetic as ``ndimage.distance_transform_edt`` (so the same values), whose
    float64 tables of the whole grid would take four times the nearest-cell table.
    """
    nearest = np.empty((2, *obstacle.shape), dtype=np.int32)
    ndimage.distance_transform_edt(~obstacle, return_distances=False, return_indices=True, indices=nearest)
    distance = np.empty(obstacle.shape, dtype=np.float32)
    columns = np.arange(obstacle.shape[1], dtype=np.int32)
    for r0 in range(0, obstacle.shape[0], rows_per_band):
        r1 = min(obstacle.shape[0], r0 + rows_per_band)
        rows = np.arange(r0, r1, dtype=np.int32)[:, None]
        dr = (nearest[0, r0:r1] - rows).astype(np.float64)
        dc = (nearest[1, r0:r1] - columns).astype(np.float64)
        distance[r0:r1] = np.sqrt(dr * dr + dc * dc).astype(np.float32) * np.float32(cell)
    return distance


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
