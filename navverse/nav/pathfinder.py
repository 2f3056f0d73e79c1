"""Build a navmesh from a z-up triangle mesh and query it with a habitat-sim-like :class:`PathFinder`.

The heavy lifting is RecastNavigation (Recast voxelizes and builds polygons, Detour stores tiles and
answers queries) through the C++ extension :mod:`navverse.nav._recast`, which converts between the
z-up world frame and Recast's y-up frame. Everything here is z-up.

Conventions
-----------
- Points are ``(3,)`` float arrays ``[x, y, z]``; point queries also take ``(N, 3)`` arrays and then
  return one result per row.
- Query points are first *snapped*: the nearest navmesh point inside a box of half sizes
  ``max_horizontal`` (x and y) and ``max_vertical`` (z) around them. A point with nothing in that box
  is off the mesh: paths to or from it are unreachable (``inf``, no points), snapped points and
  obstacle distances are NaN, islands are -1. Non-finite points are off the mesh too. No query
  raises on a far-away point.
- Paths are exact shortest paths: with every area cost 1 and no excluded area (the default), the
  polygon corridor comes from an any-angle search over the navmesh polygons (Polyanya) and the path
  is string-pulled through it, so geodesic distances are the true shortest horizontal paths of the
  navmesh (not Detour's A*, which scores polygon edge midpoints and can go around the wrong side
  of an obstacle). With area costs or excluded areas, Detour's cost-aware A* chooses the corridor
  and straight-line shortcuts that cost no more are taken; such paths minimise cost approximately.
  ``points`` are the path's corners; the geodesic distance is its length along the navmesh
  surface: exact horizontally, plus the rise and fall of the detail mesh under it (height wiggles
  below 1.5 cell heights, the voxel quantization, are ignored), so on flat ground it equals the
  length of the polyline through ``points`` and on a ramp or across a curb it follows the surface.
  Unreachable ends (another island, excluded areas) give ``inf``.
- Area costs and excluded areas apply to path queries only (:meth:`PathFinder.find_path`,
  :meth:`~PathFinder.find_path_multi`, :meth:`~PathFinder.geodesic_distance`); snapping, islands,
  random points and obstacle distances always see the whole navmesh.
- A :class:`PathFinder` is not safe to query from several threads at once (Detour's query object
  keeps search state); give each thread its own (``PathFinder.load`` or ``from_bytes``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from navverse.errors import rebuild_hint
from navverse.files import atomic_write
from navverse.nav.errors import NavMeshError

try:
    from navverse.nav import _recast
except ImportError as exc:  # pragma: no cover - depends on the installation
    raise ImportError(
        "navverse.nav's C++ extension (navverse.nav._recast) is not built or cannot load its "
        "RecastNavigation libraries: install the system package librecast-dev, then reinstall "
        "navverse (`make setup` does both)"
    ) from exc
from navverse.nav.fileformat import read_navmesh, write_navmesh
from navverse.nav.settings import NavMeshSettings
from navverse.nav.tiles import TileStore, TileStoreUse

__all__ = [
    "DEFAULT_AREA",
    "MAX_AREA_TYPE",
    "SNAP_MAX_HORIZONTAL",
    "SNAP_MAX_VERTICAL",
    "MultiGoalShortestPath",
    "PathFinder",
    "ShortestPath",
    "TopDownView",
    "build",
    "load",
]

DEFAULT_AREA = 63
"""Area id of every walkable polygon when :func:`build` gets no ``area_types`` (Recast's walkable area)."""
MAX_AREA_TYPE = 62
"""Largest area type :func:`build` accepts; 0 means never walkable."""
SNAP_MAX_HORIZONTAL = 2.0
"""Default horizontal half size (m) of the box searched when snapping a point to the navmesh."""
SNAP_MAX_VERTICAL = 2.0
"""Default vertical half size (m) of the box searched when snapping a point to the navmesh."""

_NUM_AREAS = 64
_EMPTY_POINTS = np.zeros((0, 3))
_Rng = np.random.Generator | int
# Settings fields a navmesh file holds only when they differ from their defaults.
_SAVED_WHEN_SET = ("fine_region", "fine_factor")


@dataclass(frozen=True, eq=False)
class ShortestPath:
    """A shortest path on the navmesh.

    Attributes
    ----------
    points : ndarray, shape (K, 3)
        Corners of the straight path from the snapped start to the snapped end; ``K = 0`` when
        unreachable.
    geodesic_distance : float
        3-D length of the path (m); ``inf`` when unreachable.
    """

    points: np.ndarray
    geodesic_distance: float

    @property
    def found(self) -> bool:
        """Whether the end is reachable."""
        return bool(np.isfinite(self.geodesic_distance))


@dataclass(frozen=True, eq=False)
class MultiGoalShortestPath(ShortestPath):
    """The shortest path to the closest of several ends.

    Attributes
    ----------
    closest_end_index : int
        Index (into the ends given) of the end the path reaches; -1 when none is reachable.
    """

    closest_end_index: int = -1


@dataclass(frozen=True, eq=False)
class TopDownView:
    """A top-down navigability image.

    Attributes
    ----------
    image : ndarray of bool, shape (H, W)
        True where a pixel's center is over the navmesh. Row 0 is the *largest* y (north up, like a
        map), column 0 the smallest x.
    origin : ndarray, shape (2,)
        World ``(x, y)`` of the image's top-left corner (x min, y max).
    meters_per_pixel : float
        Pixel size (m).
    """

    image: np.ndarray
    origin: np.ndarray
    meters_per_pixel: float

    def world_to_pixel(self, xy: ArrayLike) -> np.ndarray:
        """Pixel ``(row, col)`` (integer) of world ``(x, y)`` points, shape ``(..., 2)``."""
        p = np.asarray(xy, dtype=float)
        col = np.floor((p[..., 0] - self.origin[0]) / self.meters_per_pixel)
        row = np.floor((self.origin[1] - p[..., 1]) / self.meters_per_pixel)
        return np.stack([row, col], axis=-1).astype(np.int64)


def _points(value: ArrayLike, name: str) -> tuple[np.ndarray, bool]:
    """``value`` as an (N, 3) float array and whether it was a single (3,) point."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise NavMeshError(f"{name} must be numbers of shape (3,) or (N, 3)") from None
    if arr.shape == (3,):
        return arr.reshape(1, 3), True
    if arr.ndim == 2 and arr.shape[1] == 3:
        return np.ascontiguousarray(arr), False
    raise NavMeshError(f"{name} must have shape (3,) or (N, 3), got {arr.shape}")


def _point(value: ArrayLike, name: str) -> np.ndarray:
    arr, single = _points(value, name)
    if not single:
        raise NavMeshError(f"{name} must be one point of shape (3,), got {arr.shape}")
    return arr[0]


def _seed(rng: _Rng) -> int:
    """A 64-bit seed drawn from ``rng`` (a Generator, or an int seeding a fresh one)."""
    if isinstance(rng, np.random.Generator):
        gen = rng
    elif isinstance(rng, (int, np.integer)) and not isinstance(rng, bool):
        gen = np.random.default_rng(int(rng))
    else:
        raise TypeError(f"rng must be a numpy.random.Generator or an int seed, got {type(rng).__name__}")
    return int(gen.integers(0, np.iinfo(np.uint64).max, dtype=np.uint64, endpoint=True))


def _saved_settings(settings: NavMeshSettings) -> dict[str, Any]:
    """``settings`` as a navmesh file's metadata holds them (JSON values).

    The mixed-resolution fields are left out where they have their defaults, so a single-resolution
    navmesh file has the bytes it had before those fields existed, and older readers (which refuse
    unknown fields) read it; loading fills the defaults back in.
    """
    data = settings.model_dump(mode="json")
    for name in _SAVED_WHEN_SET:
        if getattr(settings, name) == NavMeshSettings.model_fields[name].default:
            del data[name]
    return data


def _positive(value: float, name: str) -> float:
    value = float(value)
    if not (value > 0 and np.isfinite(value)):
        raise NavMeshError(f"{name} must be a positive finite number, got {value}")
    return value


class PathFinder:
    """Queries on a built or loaded navmesh; names follow habitat-sim's ``PathFinder``.

    Create one with :func:`build` or :meth:`PathFinder.load`, not directly.

    Parameters
    ----------
    mesh : navverse.nav._recast.NavMesh
        The Detour navmesh.
    settings : NavMeshSettings
        The settings it was built with.
    """

    def __init__(self, mesh: _recast.NavMesh, settings: NavMeshSettings) -> None:
        self._mesh = mesh
        self._settings = settings
        # Path lengths: a surface height sample every 2 cells; height wiggles up to 1.5 cell
        # heights (voxel quantization of the navmesh surface) do not count.
        mesh.set_length_sampling(2.0 * settings.cell_size, 1.5 * settings.cell_height)
        self._area_costs: dict[int, float] = {}
        self._excluded: frozenset[int] = frozenset()
        self._area_names: dict[str, int] = {}

    def __repr__(self) -> str:
        return (
            f"PathFinder(tiles={self.num_tiles}, polygons={self.num_polygons}, "
            f"islands={self.num_islands}, navigable_area={self.navigable_area:.1f} m2)"
        )

    # ------------------------------------------------------------------ properties

    @property
    def settings(self) -> NavMeshSettings:
        """The settings the navmesh was built with."""
        return self._settings

    @property
    def bounds(self) -> np.ndarray:
        """``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` of the navmesh (m), shape (2, 3)."""
        return self._mesh.bounds

    @property
    def navigable_area(self) -> float:
        """Total navmesh surface area (m²), summed over the detail-mesh triangles."""
        return float(self._mesh.navigable_area)

    @property
    def num_islands(self) -> int:
        """Number of connected components of the navmesh."""
        return int(self._mesh.num_islands)

    @property
    def largest_island(self) -> int:
        """Index of the largest island: islands are numbered by decreasing area, so 0 (-1 if none)."""
        return 0 if self.num_islands else -1

    @property
    def island_areas(self) -> np.ndarray:
        """Area (m²) of every island, by island index (decreasing)."""
        return np.asarray(self._mesh.island_areas, dtype=float)

    @property
    def num_tiles(self) -> int:
        """Number of non-empty Detour tiles."""
        return int(self._mesh.num_tiles)

    @property
    def num_polygons(self) -> int:
        """Number of navmesh polygons."""
        return int(self._mesh.num_polygons)

    @property
    def area_names(self) -> dict[str, int]:
        """Area id of each named area (a scene's terrain classes, for a scene's navmesh; a copy)."""
        return dict(self._area_names)

    def name_areas(self, names: Mapping[str, int]) -> None:
        """Name area ids, so that costs and exclusions can be given by name (a scene's terrain classes:
        :func:`~navverse.nav.scene_navmesh.load_scene_navmesh` does it)."""
        bad = {name: area for name, area in names.items() if not 0 <= int(area) < _NUM_AREAS}
        if bad:
            raise NavMeshError(f"area ids of {bad} out of range: area ids are 0..63")
        self._area_names = {str(name): int(area) for name, area in names.items()}

    def _area_id(self, area: int | str, what: str) -> int:
        """The id of an area given by id or by name."""
        if isinstance(area, str):
            if area in self._area_names:
                return self._area_names[area]
            navigable = sorted(n for n, a in self._area_names.items() if a)
            if not navigable:
                raise NavMeshError(
                    f"{what} names area {area!r}, but this navmesh has no named areas: give area ids "
                    "(0..63), or load a scene's navmesh with navverse.nav.scene_navmesh.load_scene_navmesh, "
                    "whose areas are its terrain classes"
                )
            raise NavMeshError(f"{what} names area {area!r}; this navmesh's areas: {', '.join(navigable)}")
        if isinstance(area, bool) or not isinstance(area, (int, np.integer)):
            raise NavMeshError(f"{what}: an area is an id (0..63) or a name, not {area!r}")
        area_id = int(area)
        if not 0 <= area_id < _NUM_AREAS:
            raise NavMeshError(f"area id {area} out of range: area ids are 0..63")
        return area_id

    @property
    def area_costs(self) -> dict[int, float]:
        """Per-area path costs that differ from 1.0 (a copy)."""
        return dict(self._area_costs)

    @property
    def excluded_areas(self) -> frozenset[int]:
        """Area ids path queries never enter."""
        return self._excluded

    # ------------------------------------------------------------------ filter

    def set_area_costs(self, costs: Mapping[int | str, float]) -> None:
        """Set the cost per meter of walking on each area type (others cost 1.0).

        Detour's A* minimises the sum of segment length × area cost, so a path avoids an expensive
        area when a detour is cheaper. Returned geodesic distances stay plain lengths (m).

        Parameters
        ----------
        costs : mapping of int or str to float
            Area id (0..63), or area name (:attr:`area_names`: a scene's terrain class, e.g.
            ``{"road": 5}``), to cost. Costs must be >= 1.0: Detour's A* heuristic is the straight-line
            distance, so cheaper-than-1 areas would make it overestimate (scale costs so the cheapest
            is 1).

        Raises
        ------
        NavMeshError
            On an area id outside 0..63, an unknown area name, or a cost below 1.0.
        """
        table = [1.0] * _NUM_AREAS
        checked: dict[int, float] = {}
        for area, cost in costs.items():
            area_id = self._area_id(area, "set_area_costs")
            try:
                value = float(cost)
            except (TypeError, ValueError):
                raise NavMeshError(f"area cost {cost!r} for area {area!r} is not a number") from None
            if not (np.isfinite(value) and value >= 1.0):
                raise NavMeshError(
                    f"area cost {cost} for area {area_id} must be finite and >= 1.0; "
                    "scale the costs so the cheapest area costs 1"
                )
            table[area_id] = value
            if value != 1.0:
                checked[area_id] = value
        self._mesh.set_area_costs(table)
        self._area_costs = checked

    def set_excluded_areas(self, areas: Iterable[int | str]) -> None:
        """Forbid path queries from entering polygons of the given areas (replaces the previous set).

        Parameters
        ----------
        areas : iterable of int or str
            Area ids 0..63 or names (:attr:`area_names`); empty to allow every area again.
        """
        ids = frozenset(self._area_id(a, "set_excluded_areas") for a in areas)
        self._mesh.set_excluded_areas(sorted(ids))
        self._excluded = ids

    # ------------------------------------------------------------------ paths

    def find_path(
        self,
        start: ArrayLike,
        end: ArrayLike,
        *,
        max_horizontal: float = SNAP_MAX_HORIZONTAL,
        max_vertical: float = SNAP_MAX_VERTICAL,
    ) -> ShortestPath:
        """Shortest path between two points.

        Parameters
        ----------
        start, end : array_like, shape (3,)
            World points; each is snapped to the navmesh first.
        max_horizontal, max_vertical : float
            Half sizes (m) of the snapping box.

        Returns
        -------
        ShortestPath
            ``geodesic_distance = inf`` and no points when either point is off the mesh or the end
            is unreachable.
        """
        s, e = _point(start, "start"), _point(end, "end")
        points, length = self._mesh.find_path(s, e, float(max_horizontal), float(max_vertical))
        if not np.isfinite(length):
            return ShortestPath(_EMPTY_POINTS.copy(), float("inf"))
        return ShortestPath(points, float(length))

    def find_path_multi(
        self,
        start: ArrayLike,
        ends: ArrayLike,
        *,
        max_horizontal: float = SNAP_MAX_HORIZONTAL,
        max_vertical: float = SNAP_MAX_VERTICAL,
    ) -> MultiGoalShortestPath:
        """Shortest path to the closest (by geodesic distance) of several ends.

        Parameters
        ----------
        start : array_like, shape (3,)
            World start point.
        ends : array_like, shape (K, 3) or (3,)
            Candidate end points; off-mesh ones are skipped.
        max_horizontal, max_vertical : float
            Half sizes (m) of the snapping box.

        Returns
        -------
        MultiGoalShortestPath
            The path to the closest reachable end and its index; ``inf``, no points and index -1
            when none is reachable.
        """
        s = _point(start, "start")
        targets, _ = _points(ends, "ends")
        points, length, index = self._mesh.find_path_multi(
            s, targets, float(max_horizontal), float(max_vertical)
        )
        if not np.isfinite(length):
            return MultiGoalShortestPath(_EMPTY_POINTS.copy(), float("inf"), -1)
        return MultiGoalShortestPath(points, float(length), int(index))

    def geodesic_distance(
        self,
        start: ArrayLike,
        end_or_ends: ArrayLike,
        *,
        max_horizontal: float = SNAP_MAX_HORIZONTAL,
        max_vertical: float = SNAP_MAX_VERTICAL,
    ) -> float:
        """Geodesic distance (m) from ``start`` to a point, or to the closest of ``(K, 3)`` points.

        Returns ``inf`` when unreachable or off the mesh.
        """
        targets, single = _points(end_or_ends, "end_or_ends")
        kwargs = {"max_horizontal": max_horizontal, "max_vertical": max_vertical}
        if single:
            return self.find_path(start, targets[0], **kwargs).geodesic_distance
        return self.find_path_multi(start, targets, **kwargs).geodesic_distance

    # ------------------------------------------------------------------ points

    def snap_point(
        self,
        point: ArrayLike,
        *,
        max_vertical: float = SNAP_MAX_VERTICAL,
        max_horizontal: float = SNAP_MAX_HORIZONTAL,
    ) -> np.ndarray:
        """Nearest navmesh point(s) within a search box, NaN where there is none.

        Parameters
        ----------
        point : array_like, shape (3,) or (N, 3)
            World points.
        max_vertical, max_horizontal : float
            Half sizes (m) of the box searched around each point, along z and along x/y.

        Returns
        -------
        ndarray, same shape as ``point``
            Snapped points; rows of NaN for points with no navmesh in their box.
        """
        pts, single = _points(point, "point")
        out = self._mesh.snap(pts, float(max_horizontal), float(max_vertical))
        return out[0] if single else out

    def is_navigable(self, point: ArrayLike, *, max_y_delta: float = 0.5) -> bool | np.ndarray:
        """Whether point(s) lie over the navmesh, at most ``max_y_delta`` above or below it.

        Parameters
        ----------
        point : array_like, shape (3,) or (N, 3)
            World points.
        max_y_delta : float
            Largest *vertical* (z) distance (m) to the navmesh surface directly below or above the
            point. The name is habitat-sim's (which is y-up); here it is along z.

        Returns
        -------
        bool or ndarray of bool, shape (N,)
        """
        pts, single = _points(point, "point")
        out = self._mesh.is_navigable(pts, float(max_y_delta))
        return bool(out[0]) if single else out

    def distance_to_closest_obstacle(
        self,
        point: ArrayLike,
        *,
        max_search_radius: float = 2.0,
        max_horizontal: float = SNAP_MAX_HORIZONTAL,
        max_vertical: float = SNAP_MAX_VERTICAL,
    ) -> float | np.ndarray:
        """Distance (m) from the snapped point(s) to the nearest navmesh border.

        The navmesh border is the walkable area eroded by ``agent_radius``: add the radius for the
        approximate distance to the physical obstacle. Detour's ``findDistanceToWall``.

        Parameters
        ----------
        point : array_like, shape (3,) or (N, 3)
            World points, snapped first.
        max_search_radius : float
            Search radius (m); the result is at most this.
        max_horizontal, max_vertical : float
            Half sizes (m) of the snapping box.

        Returns
        -------
        float or ndarray, shape (N,)
            NaN for off-mesh points.
        """
        pts, single = _points(point, "point")
        radius = _positive(max_search_radius, "max_search_radius")
        out = self._mesh.distance_to_wall(pts, radius, float(max_horizontal), float(max_vertical))
        return float(out[0]) if single else out

    def get_random_navigable_point(self, rng: _Rng, *, island: int | None = None) -> np.ndarray:
        """A navmesh point drawn uniformly by surface area.

        Parameters
        ----------
        rng : numpy.random.Generator or int
            The only source of randomness: one 64-bit seed is drawn from it (an int seeds a fresh
            generator, so the same int gives the same point).
        island : int, optional
            Sample only this island.

        Returns
        -------
        ndarray, shape (3,)
            The point (NaN only for an empty navmesh).
        """
        isl = -1 if island is None else self._check_island(island)
        return self._mesh.random_point(_seed(rng), isl)[0]

    def get_random_navigable_point_near(
        self,
        center: ArrayLike,
        radius: float,
        rng: _Rng,
        *,
        max_tries: int = 100,
        max_horizontal: float = SNAP_MAX_HORIZONTAL,
        max_vertical: float = SNAP_MAX_VERTICAL,
    ) -> np.ndarray:
        """A navmesh point within ``radius`` of ``center``, reachable from it.

        ``center`` is snapped; candidates are drawn uniformly by area from the polygons connected to
        the center's polygon within ``radius`` and kept when their 3-D distance to the snapped center
        is at most ``radius`` (rejection sampling, at most ``max_tries`` draws).

        Returns
        -------
        ndarray, shape (3,)
            The point, or NaN when the center is off the mesh or every try was rejected.
        """
        c = _point(center, "center")
        r = _positive(radius, "radius")
        if int(max_tries) < 1:
            raise NavMeshError(f"max_tries must be at least 1, got {max_tries}")
        return self._mesh.random_point_near(
            c, r, _seed(rng), int(max_tries), float(max_horizontal), float(max_vertical)
        )[0]

    # ------------------------------------------------------------------ islands

    def island_of(
        self,
        point: ArrayLike,
        *,
        max_horizontal: float = SNAP_MAX_HORIZONTAL,
        max_vertical: float = SNAP_MAX_VERTICAL,
    ) -> int | np.ndarray:
        """Island index of the snapped point(s); -1 off the mesh."""
        pts, single = _points(point, "point")
        out = self._mesh.island_of(pts, float(max_horizontal), float(max_vertical))
        return int(out[0]) if single else out

    def island_area(self, island: int) -> float:
        """Area (m²) of one island."""
        return float(self._mesh.island_areas[self._check_island(island)])

    def _check_island(self, island: int) -> int:
        isl = int(island)
        if not 0 <= isl < self.num_islands:
            raise NavMeshError(f"island {island} does not exist: the navmesh has {self.num_islands} islands")
        return isl

    # ------------------------------------------------------------------ drawing

    def polygons(self) -> list[np.ndarray]:
        """Every navmesh polygon as a ``(K, 3)`` array of its corners (counter-clockwise seen from above)."""
        polys, _ = self._mesh.polygons()
        return polys

    def boundary_edges(self) -> np.ndarray:
        """The navmesh outline: polygon edges with nothing walkable across them, shape (K, 2, 3).

        Edges between polygons, within a tile or across tile borders, are left out, so drawing these
        segments outlines the walkable area (and the holes in it) without showing the tiling.
        """
        return self._mesh.boundary_edges()

    def polygon_area_types(self) -> np.ndarray:
        """Area id of every polygon, aligned with :meth:`polygons`, shape (P,) uint8."""
        _, areas = self._mesh.polygons()
        return areas

    def get_topdown_view(
        self, meters_per_pixel: float, height: float | None = None, *, eps: float = 0.5
    ) -> TopDownView:
        """A boolean navigability image over the navmesh bounds.

        Parameters
        ----------
        meters_per_pixel : float
            Pixel size (m).
        height : float, optional
            Only count navmesh surface within ``eps`` of this z (one floor of a building); None
            counts every level.
        eps : float
            Vertical tolerance (m) around ``height``.

        Returns
        -------
        TopDownView
            The image (row 0 = largest y) and the world position of its top-left corner.
        """
        mpp = _positive(meters_per_pixel, "meters_per_pixel")
        use_height = height is not None
        image, ox, oy = self._mesh.topdown(mpp, use_height, float(height) if use_height else 0.0, float(eps))
        return TopDownView(image=image, origin=np.array([ox, oy]), meters_per_pixel=mpp)

    # ------------------------------------------------------------------ files

    def to_bytes(self) -> bytes:
        """The navmesh as the bytes :meth:`save` writes."""
        return write_navmesh(
            self._mesh.to_bytes(),
            settings=_saved_settings(self._settings),
            area_costs=self._area_costs,
            excluded_areas=sorted(self._excluded),
            area_types=sorted({int(a) for a in self.polygon_area_types()}),
            navigable_area=self.navigable_area,
        )

    @classmethod
    def from_bytes(cls, data: bytes, *, source: str = "navmesh data") -> PathFinder:
        """A PathFinder from :meth:`to_bytes` output (``source`` names it in error messages)."""
        meta, tiles = read_navmesh(data, source=source)
        try:
            settings = NavMeshSettings.model_validate(meta["settings"])
        except Exception as exc:
            raise NavMeshError(
                f"{source}: its navmesh settings do not validate ({exc}): {rebuild_hint()}"
            ) from None
        finder = cls(_recast.NavMesh.from_bytes(tiles), settings)
        finder.set_area_costs({int(k): v for k, v in meta.get("area_costs", {}).items()})
        finder.set_excluded_areas(meta.get("excluded_areas", []))
        return finder

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the navmesh, its settings and its area costs/exclusions to a file (atomically).

        See :mod:`navverse.nav.fileformat` for the layout.
        """
        with atomic_write(path) as handle:
            handle.write(self.to_bytes())

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> PathFinder:
        """Read a file written by :meth:`save`.

        Raises
        ------
        NavMeshError
            If the file is missing, foreign, of another format version, or corrupt.
        """
        p = Path(path)
        try:
            data = p.read_bytes()
        except OSError as exc:
            raise NavMeshError(f"cannot read navmesh file {p}: {exc.strerror or exc}") from None
        return cls.from_bytes(data, source=str(p))


def build(
    vertices: ArrayLike,
    faces: ArrayLike,
    settings: NavMeshSettings,
    *,
    area_types: ArrayLike | None = None,
    jobs: int | None = None,
    tile_store: TileStore | None = None,
) -> PathFinder:
    """Build a navmesh from a z-up triangle mesh.

    Triangles facing up (counter-clockwise seen from above) with a slope of at most
    ``settings.agent_max_slope`` are walkable; every triangle, walkable or not, is an obstacle.

    Parameters
    ----------
    vertices : array_like, shape (N, 3)
        Vertex positions (m), z up.
    faces : array_like of int, shape (M, 3)
        Triangles as vertex indices.
    settings : NavMeshSettings
        Build settings, e.g. :data:`~navverse.nav.INDOOR` or :data:`~navverse.nav.OUTDOOR`.
    area_types : array_like of int, shape (M,), optional
        Area type per triangle: 1..62 (e.g. terrain classes), or 0 for never walkable. Walkable
        polygons keep their triangles' type as Detour area id, for :meth:`PathFinder.set_area_costs`.
        Without it every walkable polygon gets :data:`DEFAULT_AREA` (63).
    jobs : int, optional
        Most tiles built at once (threads); default: the number of CPUs.
    tile_store : TileStore, optional
        Finished tiles of earlier builds (:mod:`navverse.nav.tiles`): tiles whose input it holds are
        reused, the others built and added to it; the navmesh has the same bytes as without it.
        ``tile_store.last_use`` tells how many tiles were reused.

    Returns
    -------
    PathFinder

    Raises
    ------
    NavMeshError
        On malformed arrays (shapes, NaN, indices), or when nothing is walkable ("no walkable
        surface: ..." says why).
    """
    if not isinstance(settings, NavMeshSettings):
        raise TypeError(f"settings must be a NavMeshSettings, got {type(settings).__name__}")
    # model_copy(update=...) does not validate: check the values the extension will read.
    fields = {name: getattr(settings, name) for name in NavMeshSettings.model_fields}
    settings = NavMeshSettings().with_overrides(fields)
    try:
        verts = np.ascontiguousarray(vertices, dtype=np.float64)
    except (TypeError, ValueError):
        raise NavMeshError("vertices must be an (N, 3) array of numbers") from None
    if verts.ndim != 2 or verts.shape[1] != 3:
        raise NavMeshError(f"vertices must have shape (N, 3), got {verts.shape}")
    if not np.isfinite(verts).all():
        bad = int((~np.isfinite(verts).all(axis=1)).sum())
        raise NavMeshError(f"vertices contain NaN or infinite values ({bad} of {len(verts)} rows)")
    tris = np.asarray(faces)
    if tris.ndim != 2 or tris.shape[1] != 3:
        raise NavMeshError(f"faces must have shape (M, 3), got {tris.shape}")
    if len(tris) == 0:
        raise NavMeshError("no walkable surface: the mesh has no faces")
    if not np.issubdtype(tris.dtype, np.integer):
        raise NavMeshError(f"faces must hold integer vertex indices, got dtype {tris.dtype}")
    if tris.min() < 0 or tris.max() >= len(verts):
        raise NavMeshError(
            f"faces index vertices {int(tris.min())}..{int(tris.max())}, but there are {len(verts)} vertices"
        )
    if len(verts) >= 2**31 or len(tris) >= 2**31:
        raise NavMeshError("meshes are limited to 2**31 - 1 vertices and faces")
    if area_types is None:
        areas = np.full(len(tris), DEFAULT_AREA, dtype=np.uint8)
    else:
        raw = np.asarray(area_types)
        if raw.shape != (len(tris),):
            raise NavMeshError(f"area_types must have shape ({len(tris)},) (one per face), got {raw.shape}")
        if not np.issubdtype(raw.dtype, np.integer):
            raise NavMeshError(f"area_types must be integers, got dtype {raw.dtype}")
        if raw.size and (raw.min() < 0 or raw.max() > MAX_AREA_TYPE):
            raise NavMeshError(
                f"area_types must be in 0..{MAX_AREA_TYPE} (0 = never walkable), "
                f"got {int(raw.min())}..{int(raw.max())}"
            )
        areas = raw.astype(np.uint8)
    n_jobs = (os.cpu_count() or 1) if jobs is None else int(jobs)
    if n_jobs < 1:
        raise NavMeshError(f"jobs must be at least 1, got {jobs}")
    if tile_store is None:
        mesh = _recast.NavMesh.build(verts, tris.astype(np.int32), areas, settings.model_dump(), n_jobs)
    else:
        mesh = _build_with_store(verts, tris.astype(np.int32), areas, settings, n_jobs, tile_store)
    return PathFinder(mesh, settings)


def _build_with_store(
    verts: np.ndarray,
    tris: np.ndarray,
    areas: np.ndarray,
    settings: NavMeshSettings,
    jobs: int,
    store: TileStore,
) -> _recast.NavMesh:
    """Build reusing the tiles ``store`` holds, then store the tiles built here."""
    plan = _recast.TiledBuild(verts, tris, areas, settings.model_dump())
    inputs = (plan.tile_key(i) for i in range(plan.num_tiles))
    keys = [store.key(tile_input) if tile_input else None for tile_input in inputs]
    reuse = [store.get(key) if key else None for key in keys]
    mesh, built = plan.build(jobs, reuse)
    for key, data in zip(keys, built, strict=True):
        if key and data is not None:
            store.put(key, data)
    fresh = sum(data is not None for data in built)
    store.last_use = TileStoreUse(
        tiles=plan.num_tiles, reused=sum(key is not None for key in keys) - fresh, built=fresh
    )
    return mesh


def load(path: str | os.PathLike[str]) -> PathFinder:
    """Read a navmesh file written by :meth:`PathFinder.save` (same as :meth:`PathFinder.load`)."""
    return PathFinder.load(path)
