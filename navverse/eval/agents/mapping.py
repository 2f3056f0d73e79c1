"""Occupancy mapping from depth images: back-projection, floor estimation and a log-odds grid.

The mapping half of :mod:`navverse.eval.agents.frontier`: :func:`back_project` turns a depth image into
world points with the camera intrinsics and pose, :func:`estimate_floor` finds the floor height under
the robot, :func:`column_free_ranges` measures how far each image column sees free floor, and
:class:`LogOddsGrid` accumulates occupied and free cells as log-odds (a few contradicting views
overturn a wrong one) and grows as the robot goes; :class:`OccupancyMap` is a snapshot of it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from navverse.sim.simulator import Pose

__all__ = [
    "FREE",
    "LOGODDS_CLAMP",
    "OCCUPIED",
    "UNKNOWN",
    "LogOddsGrid",
    "OccupancyMap",
    "back_project",
    "column_free_ranges",
    "disk",
    "estimate_floor",
    "pixel_rays",
    "pose_matrix",
    "pose_yaw",
]

UNKNOWN, FREE, OCCUPIED = -1, 0, 1
"""Values of :attr:`OccupancyMap.grid`."""
_HIT, _MISS = 0.9, -0.4  # log-odds added per view
LOGODDS_CLAMP = (-2.0, 3.5)
"""Bounds of a cell's log-odds (the upper one marks a cell known to be occupied)."""
_GROW_MARGIN = 5.0  # m added beyond what must fit when the map grows


def pose_matrix(pose: np.ndarray) -> np.ndarray:
    """The 4x4 base-to-world transform of a pose ``[x, y, z, qx, qy, qz, qw]``."""
    return Pose(np.asarray(pose[:3], dtype=float), np.asarray(pose[3:7], dtype=float)).matrix()


def pose_yaw(pose: np.ndarray) -> float:
    """Heading (rad) of a pose ``[x, y, z, qx, qy, qz, qw]``."""
    return Pose(np.asarray(pose[:3], dtype=float), np.asarray(pose[3:7], dtype=float)).yaw


def pixel_rays(
    intrinsics: np.ndarray, shape: tuple[int, int], rotation: np.ndarray, *, stride: int = 1
) -> np.ndarray:
    """World directions of the rays through the centres of every ``stride``-th pixel row and column.

    Parameters
    ----------
    intrinsics : ndarray, shape (3, 3)
        ``K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``.
    shape : tuple of int
        Image height and width in pixels.
    rotation : ndarray, shape (3, 3)
        Orientation of the optical frame (x right, y down, z forward) in the world.
    stride : int
        Subsampling step in pixels.

    Returns
    -------
    ndarray, shape (ceil(H / stride), ceil(W / stride), 3)
        Directions scaled so that their optical z is 1: a ray reaches z-depth ``t`` at ``t * ray``.
    """
    fx, fy, cx, cy = intrinsics[0, 0], intrinsics[1, 1], intrinsics[0, 2], intrinsics[1, 2]
    x = (np.arange(0, shape[1], stride, dtype=np.float64) + 0.5 - cx) / fx
    y = (np.arange(0, shape[0], stride, dtype=np.float64) + 0.5 - cy) / fy
    return x[None, :, None] * rotation[:, 0] + y[:, None, None] * rotation[:, 1] + rotation[:, 2]


def back_project(
    depth: np.ndarray, intrinsics: np.ndarray, camera_to_world: np.ndarray, *, stride: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """World points of a z-depth image, through the pixel centres of every ``stride``-th row and column.

    Parameters
    ----------
    depth : ndarray, shape (H, W) or (H, W, 1)
        Z-depth in meters along the optical axis, 0 where nothing was hit.
    intrinsics : ndarray, shape (3, 3)
        ``K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``.
    camera_to_world : ndarray, shape (4, 4)
        Pose of the optical frame (x right, y down, z forward) in the world.
    stride : int
        Subsampling step in pixels.

    Returns
    -------
    points : ndarray, shape (ceil(H / stride), ceil(W / stride), 3)
        World coordinates (meaningless where ``valid`` is False).
    valid : ndarray of bool, same leading shape
        Pixels with a hit (depth > 0 and finite).
    """
    shape = (depth.shape[0], depth.shape[1])
    z = np.asarray(depth, dtype=np.float64).reshape(shape)[::stride, ::stride]
    valid = np.isfinite(z) & (z > 0.0)
    rays = pixel_rays(intrinsics, shape, camera_to_world[:3, :3], stride=stride)
    points = np.where(valid, z, 0.0)[..., None] * rays + camera_to_world[:3, 3]
    return points, valid


def estimate_floor(
    heights: np.ndarray, *, below: float, bin_size: float = 0.02, min_count: int = 30
) -> float | None:
    """The floor's height: the lowest well-populated height band among points below ``below``.

    Parameters
    ----------
    heights : ndarray, shape (N,)
        World z of points seen near the robot.
    below : float
        Only points lower than this count (e.g. a little under the robot's base).
    bin_size : float
        Height band width (m).
    min_count : int
        Fewest points a band needs; a band also needs a fifth of the fullest band's count.

    Returns
    -------
    float or None
        Median height of the points in the band and its neighbours; None with too few points.
    """
    z = heights[heights < below]
    if len(z) < min_count:
        return None
    lo = float(z.min())
    index = ((z - lo) / bin_size).astype(np.int64)
    counts = np.bincount(index)
    dense = np.nonzero(counts >= max(min_count, 0.2 * counts.max()))[0]
    if len(dense) == 0:
        return None
    first = int(dense[0])
    return float(np.median(z[(index >= first - 1) & (index <= first + 1)]))


@dataclass(frozen=True)
class OccupancyMap:
    """A snapshot of the agent's 2-D occupancy grid.

    Attributes
    ----------
    grid : ndarray of int8, shape (rows, cols)
        :data:`UNKNOWN`, :data:`FREE` or :data:`OCCUPIED`; row ``i`` spans y in
        ``[origin[1] + i * cell_size, origin[1] + (i + 1) * cell_size)``, column ``j`` likewise in x.
    origin : tuple of float
        World ``(x, y)`` of the lower-left corner of cell ``(0, 0)``.
    cell_size : float
        Cell edge (m).
    """

    grid: np.ndarray
    origin: tuple[float, float]
    cell_size: float

    def cell_of(self, xy: np.ndarray) -> np.ndarray:
        """Integer ``(row, col)`` of world points ``(..., 2)`` (may lie outside the grid)."""
        xy = np.asarray(xy, dtype=float)
        col = np.floor((xy[..., 0] - self.origin[0]) / self.cell_size)
        row = np.floor((xy[..., 1] - self.origin[1]) / self.cell_size)
        return np.stack([row, col], -1).astype(np.int64)

    def center_of(self, cells: np.ndarray) -> np.ndarray:
        """World ``(x, y)`` of the centres of cells ``(..., 2)`` given as ``(row, col)``."""
        cells = np.asarray(cells, dtype=float)
        x = self.origin[0] + (cells[..., 1] + 0.5) * self.cell_size
        y = self.origin[1] + (cells[..., 0] + 0.5) * self.cell_size
        return np.stack([x, y], -1)


class LogOddsGrid:
    """The agent's mutable map: log-odds of occupancy and which cells were ever observed."""

    def __init__(self, center: np.ndarray, *, size: float, cell: float) -> None:
        n = math.ceil(size / cell)
        self.cell = cell
        self.origin = np.floor(np.asarray(center[:2], dtype=float) / cell) * cell - (n // 2) * cell
        self.logodds = np.zeros((n, n), dtype=np.float32)
        self.observed = np.zeros((n, n), dtype=bool)

    @property
    def shape(self) -> tuple[int, int]:
        return self.logodds.shape

    def cells(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Row and column indices of world points ``(N, 2)``."""
        col = np.floor((xy[:, 0] - self.origin[0]) / self.cell).astype(np.int64)
        row = np.floor((xy[:, 1] - self.origin[1]) / self.cell).astype(np.int64)
        return row, col

    def centers(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """World ``(x, y)`` of cell centres."""
        return np.stack(
            [self.origin[0] + (cols + 0.5) * self.cell, self.origin[1] + (rows + 0.5) * self.cell], -1
        )

    def fit(self, lo: np.ndarray, hi: np.ndarray) -> None:
        """Grow the grid (keeping its cells) so that the box ``[lo, hi]`` (world xy) lies inside."""
        rows, cols = self.shape
        top = self.origin + np.array([cols, rows]) * self.cell
        if np.all(lo >= self.origin) and np.all(hi < top):
            return
        grow_lo = np.where(lo < self.origin, np.ceil((self.origin - lo + _GROW_MARGIN) / self.cell), 0)
        grow_hi = np.where(hi >= top, np.ceil((hi - top + _GROW_MARGIN) / self.cell), 0)
        pad = ((int(grow_lo[1]), int(grow_hi[1])), (int(grow_lo[0]), int(grow_hi[0])))
        self.logodds = np.pad(self.logodds, pad)
        self.observed = np.pad(self.observed, pad)
        self.origin = self.origin - grow_lo * self.cell

    def update(self, free: np.ndarray, occupied: np.ndarray) -> None:
        """Add one view's evidence: boolean masks of the cells seen free and seen occupied."""
        self.logodds[free & ~occupied] += _MISS
        self.logodds[occupied] += _HIT
        np.clip(self.logodds, *LOGODDS_CLAMP, out=self.logodds)
        self.observed |= free | occupied

    def mask(self, xy: np.ndarray) -> np.ndarray:
        """Boolean grid of the cells holding any of the world points ``(N, 2)``."""
        out = np.zeros(self.shape, dtype=bool)
        row, col = self.cells(xy)
        inside = (row >= 0) & (row < self.shape[0]) & (col >= 0) & (col < self.shape[1])
        out[row[inside], col[inside]] = True
        return out

    def occupied(self) -> np.ndarray:
        return self.observed & (self.logodds > 0.0)

    def free(self) -> np.ndarray:
        return self.observed & (self.logodds <= 0.0)

    def snapshot(self) -> OccupancyMap:
        grid = np.full(self.shape, UNKNOWN, dtype=np.int8)
        grid[self.free()] = FREE
        grid[self.occupied()] = OCCUPIED
        grid.setflags(write=False)
        return OccupancyMap(grid, (float(self.origin[0]), float(self.origin[1])), self.cell)


def column_free_ranges(
    points: np.ndarray, valid: np.ndarray, obstacle: np.ndarray, floor: np.ndarray, camera_xy: np.ndarray
) -> np.ndarray:
    """How far (horizontally) each image column sees free space.

    A column sees free floor up to its farthest floor point, but never past its nearest obstacle point.

    Parameters
    ----------
    points : ndarray, shape (R, C, 3)
        Back-projected world points.
    valid, obstacle, floor : ndarray of bool, shape (R, C)
        Points to use, those in the obstacle band, those on the floor.
    camera_xy : ndarray, shape (2,)
        The camera's horizontal position.

    Returns
    -------
    ndarray, shape (C,)
        Free range per column (m); 0 for a column with no floor point.
    """
    distance = np.hypot(points[..., 0] - camera_xy[0], points[..., 1] - camera_xy[1])
    nearest_obstacle = np.where(valid & obstacle, distance, np.inf).min(axis=0)
    farthest_floor = np.where(valid & floor, distance, 0.0).max(axis=0)
    return np.minimum(farthest_floor, nearest_obstacle)


def disk(radius_cells: float) -> np.ndarray:
    """A boolean disk structuring element of the given radius (in cells)."""
    r = math.ceil(radius_cells)
    y, x = np.mgrid[-r : r + 1, -r : r + 1]
    return x * x + y * y <= radius_cells * radius_cells
