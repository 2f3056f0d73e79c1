"""Bird's-eye-view pictures of a scene: a ray-cast top-down raster with annotations drawn on top.

:func:`raster_bev` casts one vertical ray per pixel through the scene's world mesh (Open3D
``RaycastingScene``) and records, per pixel, the hit terrain class, object instance, height and a
shaded colour. :func:`render_bev` draws that raster in meters with matplotlib, adds objects,
storefronts, indoor regions, exits, the indoor anchor and optional overlays, and writes a PNG.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import open3d as o3d
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, PathPatch
from matplotlib.patches import Polygon as PolygonPatch
from matplotlib.path import Path as MplPath
from numpy.typing import ArrayLike

from navverse.errors import SceneError
from navverse.scene.annotations import SceneAnnotations
from navverse.scene.colors import default_color, lighten
from navverse.scene.geometry import LabeledMesh, Scene

__all__ = [
    "BACKGROUND",
    "BevInfo",
    "BevOverlay",
    "BevRaster",
    "BevWindow",
    "auto_meters_per_pixel",
    "bev_window",
    "raster_bev",
    "render_bev",
]

TARGET_PIXELS = 1600
MAX_PIXELS = 4000
MIN_METERS_PER_PIXEL = 0.01
RAYS_PER_BAND = 1 << 16  # rays cast at a time: bounds the ray-casting working memory
BACKGROUND = (255, 255, 255)
OBJECT_LIGHTEN = 0.35
MAX_LEGEND_CATEGORIES = 25
BACKGROUND_CLASS = -2
OBJECT_CLASS = -1

_LIGHT = np.array([-1.0, 1.0, 1.5]) / np.linalg.norm([-1.0, 1.0, 1.5])  # from the north-west, ~47 deg up
_STEP_M = 0.05  # height jumps above this are outlined
_EDGE_SHADE = 0.72
_DPI = 100
_MARGIN_LEFT, _MARGIN_TOP, _MARGIN_BOTTOM, _LEGEND_WIDTH = 80, 50, 60, 330
_LEGEND_ROW_PX = 20


@dataclass(frozen=True, eq=False)
class BevOverlay:
    """Extra geometry drawn on a BEV picture: line segments (a path, an outline) and filled polygons
    (an area such as the navmesh).

    Parameters
    ----------
    label : str
        Legend entry.
    segments : ndarray, shape (K, 2, 2)
        Segments ``[[x0, y0], [x1, y1]]`` in world meters; may be empty.
    color : str or tuple of float
        Any matplotlib colour, for the lines and (translucent) the polygons.
    linewidth : float
        Line width in points.
    polygons : sequence of ndarray, each shape (N, 2)
        Polygons in world meters, filled with `color` at `fill_alpha`, below the segments.
    fill_alpha : float
        Opacity of the polygon fill.
    """

    label: str
    segments: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 2)))
    color: str | tuple[float, ...] = "tab:blue"
    linewidth: float = 1.0
    polygons: Sequence[np.ndarray] = ()
    fill_alpha: float = 0.3

    def __post_init__(self) -> None:
        segments = np.asarray(self.segments, dtype=np.float64)
        if segments.size == 0:
            segments = segments.reshape(0, 2, 2)
        if segments.ndim != 3 or segments.shape[1:] != (2, 2):
            raise ValueError(f"overlay segments must have shape (K, 2, 2), got {segments.shape}")
        polygons = tuple(np.asarray(p, dtype=np.float64) for p in self.polygons)
        for polygon in polygons:
            if polygon.ndim != 2 or polygon.shape[1] != 2 or len(polygon) < 3:
                raise ValueError(f"overlay polygons must have shape (N >= 3, 2), got {polygon.shape}")
        if not 0.0 <= self.fill_alpha <= 1.0:
            raise ValueError(f"fill_alpha must be in [0, 1], got {self.fill_alpha}")
        object.__setattr__(self, "segments", segments)
        object.__setattr__(self, "polygons", polygons)


@dataclass(frozen=True)
class BevInfo:
    """Where the ray-cast raster sits in the world and in the written PNG.

    Parameters
    ----------
    origin : tuple of float
        World ``(x, y)`` of the raster's top-left corner (minimum x, maximum y).
    meters_per_pixel : float
        Raster resolution.
    raster_shape : tuple of int
        ``(rows, cols)`` of the raster.
    raster_offset : tuple of int
        ``(row, col)`` of the raster's top-left pixel in the PNG (one raster pixel is one PNG pixel).
    image_shape : tuple of int
        ``(rows, cols)`` of the PNG.
    """

    origin: tuple[float, float]
    meters_per_pixel: float
    raster_shape: tuple[int, int]
    raster_offset: tuple[int, int] = (0, 0)
    image_shape: tuple[int, int] = (0, 0)

    def world_to_raster(self, xy: ArrayLike) -> np.ndarray:
        """Map world ``(x, y)`` points, shape (..., 2), to integer raster ``(row, col)``."""
        xy = np.asarray(xy, dtype=np.float64)
        col = np.floor((xy[..., 0] - self.origin[0]) / self.meters_per_pixel)
        row = np.floor((self.origin[1] - xy[..., 1]) / self.meters_per_pixel)
        return np.stack([row, col], axis=-1).astype(np.int64)

    def world_to_pixel(self, xy: ArrayLike) -> np.ndarray:
        """Map world ``(x, y)`` points, shape (..., 2), to integer PNG ``(row, col)``."""
        return self.world_to_raster(xy) + np.asarray(self.raster_offset, dtype=np.int64)


@dataclass(frozen=True, eq=False)
class BevRaster:
    """A top-down ray-cast raster of a scene (row 0 is the maximum y).

    Parameters
    ----------
    info : BevInfo
        Placement of the raster in the world.
    rgb : ndarray of uint8, shape (H, W, 3)
        Shaded colours; background is white.
    class_index : ndarray of int16, shape (H, W)
        Index into `class_names`, ``-1`` for objects, ``-2`` where no ray hit.
    instance_id : ndarray of int32, shape (H, W)
        Object instance id, 0 elsewhere.
    height : ndarray of float64, shape (H, W)
        Hit height z in meters, NaN where no ray hit.
    class_names : tuple of str
        Terrain class names.
    """

    info: BevInfo
    rgb: np.ndarray
    class_index: np.ndarray
    instance_id: np.ndarray
    height: np.ndarray
    class_names: tuple[str, ...]


def auto_meters_per_pixel(extent_m: float) -> float:
    """Return the resolution that gives the longer image side ~1600 pixels (at least 0.01 m/px).

    Parameters
    ----------
    extent_m : float
        The longer horizontal side of the scene in meters.
    """
    return max(extent_m / TARGET_PIXELS, MIN_METERS_PER_PIXEL)


def _raster_info(scene: Scene, meters_per_pixel: float | None) -> BevInfo:
    """Place the raster over the scene's bounds at the given (or automatic) resolution.

    Raises
    ------
    SceneError
        If `meters_per_pixel` is not positive or would make a side longer than 4000 pixels.
    """
    bounds = scene.annotations.bounds
    x_min, y_min, _ = bounds.min
    x_max, y_max, _ = bounds.max
    longer = max(x_max - x_min, y_max - y_min)
    if meters_per_pixel is None:
        mpp = auto_meters_per_pixel(longer)
    else:
        mpp = float(meters_per_pixel)
        if not math.isfinite(mpp) or mpp <= 0:
            raise SceneError(f"meters_per_pixel must be a positive number, got {meters_per_pixel!r}")
        if longer / mpp > MAX_PIXELS:
            raise SceneError(
                f"meters_per_pixel={mpp:g} would make a {math.ceil(longer / mpp)}-pixel image side; "
                f"the limit is {MAX_PIXELS}: use at least {longer / MAX_PIXELS:.4g}"
            )
    cols = max(1, math.ceil((x_max - x_min) / mpp - 1e-9))
    rows = max(1, math.ceil((y_max - y_min) / mpp - 1e-9))
    return BevInfo(origin=(float(x_min), float(y_max)), meters_per_pixel=mpp, raster_shape=(rows, cols))


def raster_bev(
    scene: Scene, *, meters_per_pixel: float | None = None, rays_per_band: int = RAYS_PER_BAND
) -> BevRaster:
    """Ray-cast the scene from above into a labelled, shaded raster.

    One vertical ray per pixel is cast downwards from above the scene's bounds through every
    surface of a class with ``show_in_bev`` and every object. A pixel takes the colour of the
    terrain class it hits (objects: their category colour, lightened), scaled by a hillshade from
    the hit normal. Pixels next to a height jump of more than 5 cm that the surface slope does not
    explain are darkened, so walls and steps read.

    The rays are cast and shaded in bands of whole rows, about `rays_per_band` rays at a time, so
    the working memory beyond the returned arrays does not grow with the image. The band size does
    not change the result.

    Parameters
    ----------
    scene : Scene
        The scene to draw; its ``annotations.bounds`` give the raster's extent.
    meters_per_pixel : float, optional
        Resolution; by default :func:`auto_meters_per_pixel` of the longer side.
    rays_per_band : int
        Rays cast at a time (a band holds at least one row).

    Returns
    -------
    BevRaster
        The raster and its placement (``raster_offset`` and ``image_shape`` are zero).

    Raises
    ------
    SceneError
        If `meters_per_pixel` is not positive or would make a side longer than 4000 pixels.
    ValueError
        If `rays_per_band` is not positive.
    """
    info = _raster_info(scene, meters_per_pixel)
    class_index = np.full(info.raster_shape, BACKGROUND_CLASS, dtype=np.int16)
    instance_id = np.zeros(info.raster_shape, dtype=np.int32)
    height = np.full(info.raster_shape, np.nan)
    rgb, class_names, _ = _cast_bev(
        scene, info, rays_per_band=rays_per_band, labels=(class_index, instance_id, height)
    )
    return BevRaster(info, rgb, class_index, instance_id, height, class_names)


@dataclass(frozen=True, eq=False)
class _Rows:
    """Ray hits of the raster rows ``start`` to ``stop`` (exclusive).

    Parameters
    ----------
    start : int
        The first row.
    t_hit : ndarray of float32, shape (R, W)
        Distance from the ray origin down to the hit, inf where the ray hit nothing.
    face : ndarray of uint32, shape (R, W)
        Index of the hit face (meaningless where nothing was hit).
    normal : ndarray of float32, shape (R, W, 3)
        Normal of the hit face.
    """

    start: int
    t_hit: np.ndarray
    face: np.ndarray
    normal: np.ndarray

    @property
    def stop(self) -> int:
        """One past the last row."""
        return self.start + len(self.t_hit)


def _cast_bev(
    scene: Scene,
    info: BevInfo,
    *,
    rays_per_band: int,
    labels: tuple[np.ndarray, np.ndarray, np.ndarray] | None,
) -> tuple[np.ndarray, tuple[str, ...], tuple[int, ...]]:
    """Ray-cast the scene from above (see :func:`raster_bev`), one band of rows at a time.

    Each band is cast with one row above and below it, so the height steps of its edge rows see
    their neighbours; rows the previous band already cast are reused. A pixel's values depend only
    on its own ray and its four neighbours' rays, so the bands give the raster one whole-image pass
    gives.

    Parameters
    ----------
    scene : Scene
        The scene to draw.
    info : BevInfo
        Where the raster sits (from :func:`_raster_info`).
    rays_per_band : int
        Rays cast at a time (a band holds at least one row).
    labels : tuple of ndarray, optional
        ``(class_index, instance_id, height)`` of the raster's shape, filled in as in
        :class:`BevRaster` where a ray hits (the caller initialises them for no hit); None to keep
        only the colours.

    Returns
    -------
    rgb : ndarray of uint8, shape (H, W, 3)
        Shaded colours; background is white.
    class_names : tuple of str
        Terrain class names.
    present : tuple of int
        Indices into `class_names` of the terrain classes some pixel shows, ascending.

    Raises
    ------
    ValueError
        If `rays_per_band` is not positive.
    """
    if rays_per_band < 1:
        raise ValueError(f"rays_per_band must be positive, got {rays_per_band}")
    rows, cols = info.raster_shape
    mpp = info.meters_per_pixel
    bounds = scene.annotations.bounds
    x_min, y_min, _ = bounds.min
    _, y_max, _ = bounds.max

    hidden = [name for name, tc in scene.annotations.terrain_classes.items() if not tc.show_in_bev]
    labeled = scene.world_mesh(include_objects=True, exclude_classes=hidden)
    class_names = labeled.class_names
    rgb = np.empty((rows, cols, 3), dtype=np.uint8)
    rgb[...] = BACKGROUND
    mesh = labeled.mesh
    if mesh.num_faces == 0:
        return rgb, class_names, ()

    # Cast in a local frame so float32 keeps centimetre precision far from the world origin.
    local = np.array([x_min, y_min, 0.0])
    top = max(bounds.max[2], float(mesh.vertices[:, 2].max())) + 1.0
    raycaster = o3d.t.geometry.RaycastingScene()
    raycaster.add_triangles(
        o3d.core.Tensor(_local_float32(mesh.vertices, local)),
        o3d.core.Tensor(mesh.faces.astype(np.uint32)),
    )
    xs = (np.arange(cols) + 0.5) * mpp + (x_min - local[0])
    ys = (y_max - local[1]) - (np.arange(rows) + 0.5) * mpp
    table, face_row = _face_colours(scene, labeled)
    present = np.zeros(len(class_names), dtype=bool)

    band_rows = max(1, rays_per_band // cols)
    block: _Rows | None = None
    hits_total = 0
    lone: tuple[slice, np.ndarray, np.ndarray] | None = None  # a band's only hit, shaded as the sole hit
    for r0 in range(0, rows, band_rows):
        r1 = min(r0 + band_rows, rows)
        block = _cast_rows(
            raycaster, xs, ys, top, start=max(r0 - 1, 0), stop=min(r1 + 1, rows), previous=block
        )
        hit = np.isfinite(block.t_hit)
        block_height = np.full(hit.shape, np.nan)
        block_height[hit] = top - block.t_hit[hit]
        normals = block.normal[hit].astype(np.float64)
        normals[normals[:, 2] < 0] *= -1.0
        step = _height_steps(block_height, hit, normals, mpp)

        inner = slice(r0 - block.start, r1 - block.start)
        band_hit = hit[inner]
        count = int(np.count_nonzero(band_hit))
        if count == 0:
            continue
        first = int(np.count_nonzero(hit[: inner.start]))
        band_normals = normals[first : first + count]
        face = block.face[inner][band_hit]
        colours = table[face_row[face]]
        edge = step[inner][band_hit]
        if count == 1:
            # NumPy multiplies a one-row matrix by a vector as a dot product, which can round
            # differently from the matrix-vector product several rows get: shade a band's lone hit
            # as one of two equal rows, and keep its one-row shade for a raster with no other hit.
            values = _shaded(colours.repeat(2, axis=0), band_normals.repeat(2, axis=0), edge.repeat(2))[:1]
            lone = (slice(r0, r1), band_hit, _shaded(colours, band_normals, edge))
        else:
            values = _shaded(colours, band_normals, edge)
        rgb[r0:r1][band_hit] = values
        hits_total += count
        terrain = labeled.class_index[face]
        present[terrain[terrain >= 0]] = True
        if labels is not None:
            class_index, instance_id, height = labels
            class_index[r0:r1][band_hit] = terrain
            instance_id[r0:r1][band_hit] = labeled.instance_id[face]
            height[r0:r1][band_hit] = block_height[inner][band_hit]
    if hits_total == 1 and lone is not None:
        band, mask, values = lone
        rgb[band][mask] = values
    return rgb, class_names, tuple(int(i) for i in np.flatnonzero(present))


def _local_float32(vertices: np.ndarray, local: np.ndarray, *, chunk: int = 1 << 16) -> np.ndarray:
    """``(vertices - local).astype(np.float32)``, subtracted in float64 one chunk of rows at a time."""
    out = np.empty(vertices.shape, dtype=np.float32)
    for start in range(0, len(vertices), chunk):
        out[start : start + chunk] = vertices[start : start + chunk] - local
    return out


def _cast_rows(
    raycaster: o3d.t.geometry.RaycastingScene,
    xs: np.ndarray,
    ys: np.ndarray,
    top: float,
    *,
    start: int,
    stop: int,
    previous: _Rows | None,
) -> _Rows:
    """Cast straight down through the pixel centres of rows `start` to `stop`, reusing `previous`.

    Parameters
    ----------
    raycaster : RaycastingScene
        The scene's triangles in the local frame.
    xs, ys : ndarray of float64
        Local x of every column's and local y of every row's pixel centre.
    top : float
        Local height the rays start from.
    start, stop : int
        The rows wanted.
    previous : _Rows, optional
        The rows cast last; those of them from `start` on are reused (it must end by `stop`).

    Returns
    -------
    _Rows
        The hits of rows `start` to `stop`.
    """
    parts: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    reused = 0
    if previous is not None and previous.stop > start:
        reused = previous.stop - start
        parts.append((previous.t_hit[-reused:], previous.face[-reused:], previous.normal[-reused:]))
    if start + reused < stop:
        rays = np.zeros((stop - start - reused, len(xs), 6), dtype=np.float32)
        rays[..., 0] = xs
        rays[..., 1] = ys[start + reused : stop, None]
        rays[..., 2] = top
        rays[..., 5] = -1.0
        hits = raycaster.cast_rays(o3d.core.Tensor(rays))
        parts.append(
            (hits["t_hit"].numpy(), hits["primitive_ids"].numpy(), hits["primitive_normals"].numpy())
        )
    if len(parts) == 1:
        return _Rows(start, *parts[0])
    t_hit, face, normal = (np.concatenate(arrays) for arrays in zip(*parts, strict=True))
    return _Rows(start, t_hit, face, normal)


def _face_colours(scene: Scene, labeled: LabeledMesh) -> tuple[np.ndarray, np.ndarray]:
    """A table of base colours and each face's row in it.

    Terrain faces take their class colour; faces of an object take its category colour,
    lightened (faces of an id no object has: the first terrain class's colour).

    Parameters
    ----------
    scene : Scene
        The scene: its terrain class colours and object categories.
    labeled : LabeledMesh
        The scene's world mesh as ray cast.

    Returns
    -------
    table : ndarray of float64, shape (K, 3)
        Colours in 0..255: the terrain classes in ``labeled.class_names`` order (white when there
        are none), then the object categories in name order.
    face_row : ndarray of int16 (int32 for a longer table), shape (M,)
        Row of `table` for every face of ``labeled.mesh``.
    """
    terrain = [scene.annotations.terrain_classes[n].color for n in labeled.class_names] or [BACKGROUND]
    categories = {o.annotation.id: o.annotation.category for o in scene.objects}
    names = sorted(set(categories.values()))
    table = np.array(terrain + [lighten(default_color(c), OBJECT_LIGHTEN) for c in names], dtype=float)
    row_type = np.int16 if len(table) <= np.iinfo(np.int16).max else np.int32
    face_row = np.clip(labeled.class_index, 0, None).astype(row_type)
    if categories:
        name_row = {name: len(terrain) + i for i, name in enumerate(names)}
        ids = np.array(sorted(categories), dtype=np.int64)
        id_rows = np.array([name_row[categories[i]] for i in ids.tolist()], dtype=row_type)
        at = np.minimum(np.searchsorted(ids, labeled.instance_id), len(ids) - 1)
        is_object = ids[at] == labeled.instance_id
        face_row[is_object] = id_rows[at[is_object]]
    return table, face_row


def _shaded(colours: np.ndarray, normals: np.ndarray, edge: np.ndarray) -> np.ndarray:
    """Colours of hit pixels: base colour times the hillshade of the hit normal, darker at steps.

    Parameters
    ----------
    colours : ndarray of float64, shape (N, 3)
        Base colours in 0..255.
    normals : ndarray of float64, shape (N, 3)
        Hit normals, pointing up.
    edge : ndarray of bool, shape (N,)
        Whether the pixel is next to a height step.

    Returns
    -------
    ndarray of uint8, shape (N, 3)
        The shaded colours.
    """
    shade = np.clip((normals @ _LIGHT) / _LIGHT[2], 0.55, 1.15)
    shade = shade * np.where(edge, _EDGE_SHADE, 1.0)
    return np.clip(np.rint(colours * shade[:, None]), 0, 255).astype(np.uint8)


def _height_steps(height: np.ndarray, hit: np.ndarray, normals: np.ndarray, mpp: float) -> np.ndarray:
    """Mark pixels next to a height jump that the hit surfaces' slopes do not explain."""
    nz = np.maximum(normals[:, 2], 0.05)
    grad_x = np.full(height.shape, np.nan)
    grad_y = np.full(height.shape, np.nan)
    grad_x[hit] = -normals[:, 0] / nz
    grad_y[hit] = -normals[:, 1] / nz
    step = np.zeros(height.shape, dtype=bool)
    with np.errstate(invalid="ignore"):
        # Neighbour to the right is +mpp in x; neighbour below is -mpp in y. A jump counts when
        # extending either pixel's surface plane misses the other pixel's height.
        miss_x = (
            np.minimum(
                np.abs(height[:, 1:] - (height[:, :-1] + grad_x[:, :-1] * mpp)),
                np.abs(height[:, :-1] - (height[:, 1:] - grad_x[:, 1:] * mpp)),
            )
            > _STEP_M
        )
        miss_y = (
            np.minimum(
                np.abs(height[1:] - (height[:-1] - grad_y[:-1] * mpp)),
                np.abs(height[:-1] - (height[1:] + grad_y[1:] * mpp)),
            )
            > _STEP_M
        )
    step[:, :-1] |= miss_x
    step[:, 1:] |= miss_x
    step[:-1] |= miss_y
    step[1:] |= miss_y
    return step


def _rgb01(color: tuple[int, int, int]) -> tuple[float, float, float]:
    return (color[0] / 255.0, color[1] / 255.0, color[2] / 255.0)


def _marker(marker: str, color: str, label: str, *, size: float = 6.0) -> Line2D:
    return Line2D(
        [], [], marker=marker, linestyle="", markersize=size, markerfacecolor=color, markeredgecolor="black",
        markeredgewidth=0.5, label=label,
    )  # fmt: skip


def _compound_path(polygons: Sequence[np.ndarray]) -> MplPath:
    """All polygons as closed sub-paths of one path (nonzero winding: opposite winding cuts holes)."""
    vertices = np.concatenate([np.vstack([p, p[:1]]) for p in polygons])
    codes = np.concatenate(
        [[MplPath.MOVETO, *[MplPath.LINETO] * (len(p) - 1), MplPath.CLOSEPOLY] for p in polygons]
    ).astype(MplPath.code_type)
    return MplPath(vertices, codes)


def _draw_rooms_and_doors(ax: Axes, ann: SceneAnnotations, handles: list[Artist]) -> None:
    """Room outlines with their type at a point inside, and each doorway as a bar across its opening."""
    from shapely.geometry import Polygon as ShapelyPolygon

    for room in ann.rooms:
        ring = np.asarray(room.polygon)
        ax.add_patch(
            PolygonPatch(ring, closed=True, fill=False, edgecolor=(0.25, 0.25, 0.3), linestyle=(0, (4, 3)),
                         linewidth=0.7, zorder=2)
        )  # fmt: skip
        inside = ShapelyPolygon(ring).representative_point()
        ax.text(inside.x, inside.y, room.room_type.replace("_", " "), fontsize=7, ha="center", va="center",
                zorder=8, bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "alpha": 0.75,
                                "edgecolor": "none"})  # fmt: skip
    if ann.rooms:
        handles.append(
            Line2D([], [], color=(0.25, 0.25, 0.3), linestyle=(0, (4, 3)), linewidth=0.7, label="room")
        )
    if ann.doors:
        bars = []
        for door in ann.doors:
            along = np.array([-math.sin(door.facing), math.cos(door.facing)]) * door.width / 2
            center = np.asarray(door.center[:2])
            bars.append([center - along, center + along])
        ax.add_collection(LineCollection(bars, colors="tab:green", linewidths=3.0, zorder=6))
        handles.append(Line2D([], [], color="tab:green", linewidth=3.0, label="doorway"))


def _draw_buildings(ax: Axes, ann: SceneAnnotations, handles: list[Artist]) -> None:
    """Each building's footprint, its id, and a short outward tick at the middle of each facade."""
    ticks = []
    for building in ann.buildings:
        ring = np.asarray(building.footprint)
        ax.add_patch(
            PolygonPatch(ring, closed=True, fill=False, edgecolor=(0.15, 0.15, 0.15), linewidth=1.0, zorder=2)
        )
        corner = ring[np.argmax(ring[:, 1] - 1e-3 * ring[:, 0])]  # the top-left corner, above the rooms
        ax.text(corner[0], corner[1], f" B{building.id}", fontsize=8, ha="left", va="bottom", zorder=9,
                color=(0.15, 0.15, 0.15), fontweight="bold")  # fmt: skip
        for facade in building.facades:
            middle = 0.5 * (np.asarray(facade.segment[0]) + np.asarray(facade.segment[1]))
            ticks.append([middle, middle + 0.6 * np.asarray(facade.normal)])
    if ticks:
        ax.add_collection(LineCollection(ticks, colors=(0.15, 0.15, 0.15), linewidths=1.0, zorder=2))
    if ann.buildings:
        handles.append(Line2D([], [], color=(0.15, 0.15, 0.15), linewidth=1.0, label="building, facades"))


def _draw_annotations(ax: Axes, ann: SceneAnnotations, overlays: Sequence[BevOverlay]) -> list[Artist]:
    """Draw regions, objects, storefronts, exits, the anchor and overlays; return legend handles."""
    handles: list[Artist] = []
    _draw_buildings(ax, ann, handles)
    _draw_rooms_and_doors(ax, ann, handles)
    for polygon in ann.indoor_polygons:
        ax.add_patch(
            PolygonPatch(np.asarray(polygon), closed=True, fill=False, edgecolor="tab:purple", linestyle="--",
                         linewidth=1.2, zorder=2)
        )  # fmt: skip
    if ann.indoor_polygons:
        handles.append(Line2D([], [], color="tab:purple", linestyle="--", label="indoor region"))
    for category in sorted({o.category for o in ann.objects}):
        centers = np.array([o.center[:2] for o in ann.objects if o.category == category])
        ax.scatter(centers[:, 0], centers[:, 1], s=22, color=_rgb01(default_color(category)),
                   edgecolors="black", linewidths=0.5, zorder=3)  # fmt: skip
    if ann.storefronts:
        centers = np.array([s.center[:2] for s in ann.storefronts])
        ax.scatter(centers[:, 0], centers[:, 1], marker="s", s=40, color="yellow", edgecolors="black",
                   linewidths=0.7, zorder=4)  # fmt: skip
        handles.append(_marker("s", "yellow", "storefront"))
    for exit_ in ann.exits:
        # Marker (3, 0, angle) is a triangle pointing up (+y) rotated by `angle` degrees.
        ax.scatter([exit_.center[0]], [exit_.center[1]], marker=(3, 0, math.degrees(exit_.facing) - 90.0),
                   s=70, color="red", edgecolors="black", linewidths=0.5, zorder=5)  # fmt: skip
    if ann.exits:
        handles.append(_marker("^", "red", "exit"))
    if ann.indoor_anchor is not None:
        x, y = ann.indoor_anchor[:2]
        ax.scatter([x], [y], marker="*", s=220, color="red", edgecolors="black", linewidths=0.6, zorder=6)
        handles.append(_marker("*", "red", "indoor anchor", size=12.0))
    for overlay in overlays:
        if overlay.polygons:
            # One compound path: coverage is summed over it, so edges shared by two polygons leave
            # no seam (separate translucent polygons would show every shared edge).
            ax.add_patch(
                PathPatch(_compound_path(overlay.polygons), facecolor=overlay.color, edgecolor="none",
                          alpha=overlay.fill_alpha, zorder=1.5)
            )  # fmt: skip
            handles.append(Patch(facecolor=overlay.color, alpha=overlay.fill_alpha, edgecolor=overlay.color,
                                 label=overlay.label))  # fmt: skip
        if len(overlay.segments):
            ax.add_collection(
                LineCollection(overlay.segments, colors=overlay.color, linewidths=overlay.linewidth, zorder=7)
            )
            if not overlay.polygons:
                handles.append(
                    Line2D([], [], color=overlay.color, linewidth=overlay.linewidth, label=overlay.label)
                )
    return handles


def _add_legends(fig: Figure, handles: list[Artist], categories: list[str], *, x: float, top: float) -> None:
    """Place the terrain/marker legend and, below it, the object-category legend (figure fractions)."""
    legend_kw = {"loc": "upper left", "fontsize": 8, "title_fontsize": 9, "frameon": True}
    if handles:
        legend = fig.legend(handles=handles, bbox_to_anchor=(x, top), title="terrain", **legend_kw)
        box = legend.get_window_extent(fig.canvas.get_renderer())
        top = (box.y0 - 12) / fig.bbox.height
    if categories:
        shown = categories[:MAX_LEGEND_CATEGORIES]
        title = "objects" if len(shown) == len(categories) else f"objects ({len(shown)} of {len(categories)})"
        object_handles = [_marker("o", _rgb01(default_color(c)), c, size=5.0) for c in shown]
        fig.legend(handles=object_handles, bbox_to_anchor=(x, top), title=title, **legend_kw)


def render_bev(
    scene: Scene,
    out_path: Path,
    *,
    meters_per_pixel: float | None = None,
    overlays: Sequence[BevOverlay] = (),
    rays_per_band: int = RAYS_PER_BAND,
) -> BevInfo:
    """Write a bird's-eye-view PNG of the scene.

    The ray-cast raster (see :func:`raster_bev`) is drawn one raster pixel per PNG pixel on axes in
    meters. On top: objects as points coloured by category, storefronts as yellow squares, indoor
    regions as dashed outlines, exits as red triangles pointing outwards, the indoor anchor as a red
    star, then `overlays`. Legends for terrain classes present, markers and (up to 25) object
    categories sit right of the map. The PNG carries no software version, so the same scene gives
    the same bytes.

    Parameters
    ----------
    scene : Scene
        The scene to draw.
    out_path : Path
        The PNG to write.
    meters_per_pixel : float, optional
        Raster resolution; automatic by default (longer side ~1600 px).
    overlays : sequence of BevOverlay
        Extra line collections, drawn in order above everything else.
    rays_per_band : int
        Rays cast at a time (see :func:`raster_bev`); the picture does not depend on it.

    Returns
    -------
    BevInfo
        How world coordinates map to PNG pixels.
    """
    info = _raster_info(scene, meters_per_pixel)
    rgb, class_names, present = _cast_bev(scene, info, rays_per_band=rays_per_band, labels=None)
    ann = scene.annotations
    rows, cols = info.raster_shape
    mpp = info.meters_per_pixel
    x0, y_top = info.origin
    extent = (x0, x0 + cols * mpp, y_top - rows * mpp, y_top)

    terrain_handles: list[Artist] = [
        Patch(facecolor=_rgb01(ann.terrain_classes[class_names[i]].color), edgecolor="black",
              linewidth=0.5, label=class_names[i])
        for i in present
    ]  # fmt: skip
    categories = sorted({o.category for o in ann.objects})
    legend_rows = len(terrain_handles) + 4 + len(overlays) + min(len(categories), MAX_LEGEND_CATEGORIES)
    width = _MARGIN_LEFT + cols + _LEGEND_WIDTH
    height = max(_MARGIN_TOP + rows + _MARGIN_BOTTOM, _MARGIN_TOP + legend_rows * _LEGEND_ROW_PX + 120)

    # Size the figure in whole pixels and place the axes so one raster pixel is one PNG pixel.
    fig = Figure(figsize=(width / _DPI, height / _DPI), dpi=_DPI)
    FigureCanvasAgg(fig)
    ax = fig.add_axes(
        (_MARGIN_LEFT / width, (height - _MARGIN_TOP - rows) / height, cols / width, rows / height)
    )
    # Drawn as RGBA: matplotlib resamples an RGB image as float64 RGBA but an RGBA one as float32,
    # half the memory, and every uint8 level comes out of either unchanged (the same PNG).
    rgba = np.empty((rows, cols, 4), dtype=np.uint8)
    rgba[..., :3] = rgb
    rgba[..., 3] = 255
    del rgb
    ax.imshow(rgba, extent=extent, origin="upper", interpolation="nearest", aspect="auto", zorder=0)
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{ann.scene_id} ({ann.scene_type})")
    marker_handles = _draw_annotations(ax, ann, overlays)
    _add_legends(
        fig, terrain_handles + marker_handles, categories,
        x=(_MARGIN_LEFT + cols + 15) / width, top=1.0 - _MARGIN_TOP / height,
    )  # fmt: skip
    fig.savefig(Path(out_path), dpi=_DPI, metadata={"Software": None})
    return BevInfo(
        origin=info.origin,
        meters_per_pixel=mpp,
        raster_shape=(rows, cols),
        raster_offset=(_MARGIN_TOP, _MARGIN_LEFT),
        image_shape=(height, width),
    )


@dataclass(frozen=True, eq=False)
class BevWindow:
    """A square of a scene's top-down raster around a point, resized to a picture, and where world
    points fall in it.

    Parameters
    ----------
    image : ndarray of uint8, shape (H, W, 3)
        The picture (row 0 at the square's largest y).
    info : BevInfo
        The placement of the whole raster the square was cut from.
    corner : tuple of int
        ``(row, col)`` of the square's top-left pixel in that raster.
    scale : float
        Picture pixels per raster pixel.
    """

    image: np.ndarray
    info: BevInfo
    corner: tuple[int, int]
    scale: float

    def pixel(self, xy: ArrayLike) -> tuple[float, float]:
        """Picture ``(x, y)`` of a world point ``(x, y)`` (for drawing on the picture with Pillow)."""
        row, col = self.info.world_to_raster(np.asarray(xy, dtype=np.float64))
        return ((col - self.corner[1]) * self.scale, (row - self.corner[0]) * self.scale)


def bev_window(scene: Scene, centre: ArrayLike, side: float, *, pixels: int = 900) -> BevWindow:
    """The top-down raster of the `side` m square around `centre`, resized to `pixels` wide.

    The whole scene is ray cast at the finest resolution :func:`raster_bev` allows (at least
    6 cm per pixel), then the square is cut out and resized (Lanczos).
    """
    from PIL import Image

    lo, hi = np.asarray(scene.annotations.bounds.min[:2]), np.asarray(scene.annotations.bounds.max[:2])
    extent = float((hi - lo).max())
    info = _raster_info(scene, max(0.06, extent / (MAX_PIXELS - 100)))
    rgb, _, _ = _cast_bev(scene, info, rays_per_band=RAYS_PER_BAND, labels=None)
    middle = np.asarray(centre, dtype=np.float64)[:2]
    (r0, c0), (r1, c1) = info.world_to_raster(
        middle + np.array([[-side / 2, side / 2], [side / 2, -side / 2]])
    )
    r0, c0 = max(int(r0), 0), max(int(c0), 0)
    crop = Image.fromarray(rgb[r0 : int(r1), c0 : int(c1)])
    scale = pixels / crop.width
    crop = crop.resize((pixels, round(crop.height * scale)), Image.Resampling.LANCZOS)
    return BevWindow(np.asarray(crop), info, (r0, c0), scale)
