"""Where a robot fits in a room: a floor grid with furniture footprints, and its connectivity.

The furnisher asks, before keeping each piece of furniture, whether the robot can still reach every
doorway of the room and nearly all of its free floor. The grid covers the room's interior; cells
whose centre is at least ``robot_radius`` from any obstacle or wall are the robot's configuration
space (as the navmesh erodes the floor by its agent radius).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy import ndimage

from navverse.indoor.floorplan import Rect

__all__ = ["ROBOT_RADIUS", "FreeSpace", "footprint_corners"]

ROBOT_RADIUS = 0.65
"""Clearance kept for the robot (m): the navmesh agent radius (0.6) plus a margin."""


def footprint_corners(center: Sequence[float], size: Sequence[float], yaw: float) -> np.ndarray:
    """Corners (4, 2) of the rectangle ``size[0] x size[1]`` centred at ``center`` and turned by ``yaw``."""
    c, s = math.cos(yaw), math.sin(yaw)
    hx, hy = size[0] / 2, size[1] / 2
    local = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
    return local @ np.array([[c, s], [-s, c]]) + np.asarray(center[:2], dtype=float)


class FreeSpace:
    """The robot's free space in one room.

    Parameters
    ----------
    interior : Rect
        The room's free floor (inside its walls).
    anchors : sequence of (x, y)
        Points the robot must be able to reach (in front of each doorway).
    cell : float
        Grid resolution (m).
    robot_radius : float
        Clearance from obstacles (m).
    """

    def __init__(
        self,
        interior: Rect,
        anchors: Sequence[tuple[float, float]],
        *,
        cell: float = 0.1,
        robot_radius: float = ROBOT_RADIUS,
    ) -> None:
        self.interior = interior
        self.cell = cell
        self.robot_radius = robot_radius
        self.cols = max(1, math.floor(interior.width / cell))
        self.rows = max(1, math.floor(interior.depth / cell))
        self.blocked = np.zeros((self.rows, self.cols), dtype=bool)
        xs = interior.x0 + (np.arange(self.cols) + 0.5) * interior.width / self.cols
        ys = interior.y0 + (np.arange(self.rows) + 0.5) * interior.depth / self.rows
        self._x, self._y = np.meshgrid(xs, ys)
        self.anchors = [self._cell_of(a) for a in anchors]

    def _cell_of(self, point: tuple[float, float]) -> tuple[int, int]:
        col = int((point[0] - self.interior.x0) / self.interior.width * self.cols)
        row = int((point[1] - self.interior.y0) / self.interior.depth * self.rows)
        return min(max(row, 0), self.rows - 1), min(max(col, 0), self.cols - 1)

    def mask(self, corners: np.ndarray) -> np.ndarray:
        """Cells whose centre lies in the convex polygon ``corners`` (counter-clockwise, (K, 2))."""
        inside = np.ones(self.blocked.shape, dtype=bool)
        for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True):
            inside &= (b[0] - a[0]) * (self._y - a[1]) - (b[1] - a[1]) * (self._x - a[0]) >= 0
        return inside

    def configuration_space(self, blocked: np.ndarray | None = None) -> np.ndarray:
        """Cells where the robot's centre fits, for ``blocked`` (default: the current obstacles)."""
        occupied = self.blocked if blocked is None else blocked
        padded = np.pad(~occupied, 1, constant_values=False)  # the walls around the room
        distance = ndimage.distance_transform_edt(padded)[1:-1, 1:-1] * self.cell
        return distance >= self.robot_radius + self.cell / 2

    def connected_with(self, extra: np.ndarray, *, min_share: float = 0.97) -> bool:
        """Whether, with ``extra`` cells blocked too, every anchor is in one component of the free
        space that holds at least ``min_share`` of it."""
        space = self.configuration_space(self.blocked | extra)
        total = int(space.sum())
        if total == 0:
            return False
        labels, _ = ndimage.label(space)
        anchor_labels = {int(labels[r, c]) for r, c in self.anchors}
        if 0 in anchor_labels or len(anchor_labels) > 1:
            return False
        if not anchor_labels:
            return int(np.bincount(labels.ravel())[1:].max()) >= min_share * total
        (label,) = anchor_labels
        return int((labels == label).sum()) >= min_share * total

    def block(self, extra: np.ndarray) -> None:
        """Add ``extra`` cells to the obstacles."""
        self.blocked |= extra
